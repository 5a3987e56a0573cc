// The shared constants equal the values the code used before it shared them (the copies they
// replace: each file's own pi, 2 pi, degree factor), so replacing a copy changes no number.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace {

// Exact: the same double.
static_assert(kPi == 3.141592653589793238463, "pi as the milling and sync copies wrote it");
static_assert(kPi == 3.14159265358979323846, "pi as the frf copies wrote it");
static_assert(kTwoPi == 6.283185307179586476925, "2 pi as milling/simulation.cpp wrote it");
static_assert(kTwoPi == 6.283185307179586476925286766559, "2 pi as dynamics and sync wrote it");
static_assert(kTwoPi == 2.0 * 3.14159265358979323846, "2 pi as frf wrote it");
static_assert(kDegToRad == 0.017453292519943295, "the factor app/cut_estimation.cpp wrote");
static_assert(kRadToDeg == 57.29577951308232, "the factor app/simulate.cpp wrote");
static_assert(kMToUm == 1e6 && kMToMm == 1e3 && kMmToM == 1e-3, "unit factors");

TEST(Constants, PiIsTheLibrarysPi) {
  EXPECT_EQ(kPi, std::acos(-1.0));  // the correctly rounded pi of the C library
  EXPECT_EQ(kTwoPi, 2.0 * kPi);
}

TEST(Constants, UnitFactorsConvertKnownValues) {
  // 1e-15 relative: one rounding of each product.
  EXPECT_NEAR(180.0 * kDegToRad, kPi, 1e-15 * kPi);
  EXPECT_NEAR(kPi * kRadToDeg, 180.0, 1e-15 * 180.0);
  // 60 rpm is one revolution a second: 2 pi rad/s; 15,000 rpm (000 sec. 5.2) 1570.8 rad/s.
  EXPECT_NEAR(60.0 * kRpmToRadPerS, kTwoPi, 1e-15 * kTwoPi);
  EXPECT_NEAR(15000.0 * kRpmToRadPerS, 500.0 * kPi, 1e-12);
  EXPECT_EQ(kSecondsPerMinute / 15000.0, 0.004);  // one revolution at 15,000 rpm, s
}

}  // namespace
}  // namespace chatterlab
