#include "app/core/format.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chatterlab::app {
namespace {

TEST(Format, SignificantDigitsPlainAndScientific) {
  EXPECT_EQ(fmt_sig(891.8014, 4), "891.8");
  EXPECT_EQ(fmt_sig(0.031357, 4), "0.03136");
  EXPECT_EQ(fmt_sig(9.8453e5, 4), "9.845e+05");
  EXPECT_EQ(fmt_sig(2.5e-4, 3), "2.50e-04");
  EXPECT_EQ(fmt_sig(std::nan(""), 3), "n/a");
}

TEST(Format, FixedHasNoNegativeZero) {
  EXPECT_EQ(fmt_fixed(-0.001, 2), "0.00");
  EXPECT_EQ(fmt_fixed(-0.01, 2), "-0.01");
  EXPECT_EQ(fmt_fixed(37.364999, 2), "37.36");
  EXPECT_EQ(fmt_fixed(INFINITY, 1), "n/a");
}

}  // namespace
}  // namespace chatterlab::app
