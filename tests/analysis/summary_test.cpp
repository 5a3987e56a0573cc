#include "analysis/common/summary.h"

#include <gtest/gtest.h>

namespace chatterlab {
namespace {

TEST(StepSummary, DefaultIsNotRunAndNotOk) {
  StepSummary s;
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.message, "not run");
  s.succeed();
  EXPECT_TRUE(s.ok);
  s.fail("x.yaml: key 'axis' missing");
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.message, "x.yaml: key 'axis' missing");
}

}  // namespace
}  // namespace chatterlab
