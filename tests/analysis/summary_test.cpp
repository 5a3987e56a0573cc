#include "analysis/common/summary.h"

#include <gtest/gtest.h>

namespace chatterlab {
namespace {

TEST(StepSummary, DefaultIsNotRunAndNotOk) {
  StepSummary s;
  EXPECT_EQ(s.status, StepStatus::kNotRun);
  EXPECT_FALSE(s.ok());
  EXPECT_FALSE(s.ran());
  EXPECT_EQ(s.brief_report(), "not run");
  EXPECT_EQ(s.full_report(), "not run");
  s.succeed();
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(s.full_report(), "ok: ok");
  s.fail("x.yaml: key 'axis' missing", "the test is skipped");
  s.warnings.push_back("bounce at 1.2 s");
  EXPECT_FALSE(s.ok());
  EXPECT_TRUE(s.failed());
  EXPECT_EQ(s.brief_report(), "x.yaml: key 'axis' missing");
  EXPECT_EQ(s.full_report(),
            "failed: x.yaml: key 'axis' missing\nthe test is skipped\nwarning: bounce at 1.2 s");
}

}  // namespace
}  // namespace chatterlab
