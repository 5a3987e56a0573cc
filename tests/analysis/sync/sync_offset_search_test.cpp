#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/sync/offset_search.h"

namespace chatterlab {
namespace sync {
namespace {

// A revolution with two unequal tooth passes: a damped response after each entry, the second
// tooth four times the first (the shape of 000 figs 5.9-5.14).
double tooth_response(double theta, double amplitude) {
  const double u = std::fmod(theta + 4 * kPi, 2 * kPi);  // angle since the tooth's entry
  return amplitude * std::exp(-1.5 * u) * std::sin(5.0 * u);
}
double shape_x(double theta, double a1, double a2) {
  return tooth_response(theta, a1) + tooth_response(theta - kPi, a2);
}
double shape_y(double theta, double a1, double a2) {
  return 0.5 * tooth_response(theta - 0.3, a1) + 0.5 * tooth_response(theta - kPi - 0.3, a2);
}

// Simulated revolution on S points, measured one on N points with measured(phi) =
// simulated(phi + offset).
RevolutionMatcher make(double offset_deg, double a1, double a2, int S = 1600, int N = 400) {
  Eigen::VectorXd sx(S), sy(S), mx(N), my(N);
  for (int a = 0; a < S; ++a) {
    const double th = 2 * kPi * a / S;
    sx[a] = shape_x(th, a1, a2);
    sy[a] = shape_y(th, a1, a2);
  }
  for (int j = 0; j < N; ++j) {
    const double th = 2 * kPi * j / N + offset_deg * kDegToRad;
    mx[j] = shape_x(th, a1, a2);
    my[j] = shape_y(th, a1, a2);
  }
  return RevolutionMatcher(mx, my, sx, sy);
}

double circular_distance_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d < 0) d += 360.0;
  return std::min(d, 360.0 - d);
}

// Linear interpolation of the simulated revolution at 1600 points moves the minimum by far less
// than a grid step (0.225 deg); 0.01 deg is ten times finer than the 0.1 deg asked.
constexpr double kNoiseFreeTolDeg = 0.01;

TEST(OffsetSearch, RecoversAKnownShiftOfUnequalTeeth) {
  const RevolutionMatcher m = make(147.3, 1e-6, 4e-6);
  const OffsetSearch s = search_offset(m, 2);
  EXPECT_LT(circular_distance_deg(s.offset_angle_deg, 147.3), kNoiseFreeTolDeg)
      << s.offset_angle_deg;
  EXPECT_EQ(s.candidate_deg.size(), 360);
  EXPECT_EQ(s.error_m.size(), 360);
  EXPECT_EQ(s.candidate_deg[1], 1.0);
  // The teeth swapped (offset + 180) fit worse: the runner-up is there and far from a tie.
  EXPECT_LT(circular_distance_deg(s.runner_up_deg, 327.3), 5.0) << s.runner_up_deg;
  EXPECT_GT(s.runner_up_ratio, 10.0);
  EXPECT_FALSE(s.ambiguous);
  // The error at the offset is the interpolation error alone.
  EXPECT_LT(s.rms_error_m, 1e-3 * m.measured_rms_m());
}

TEST(OffsetSearch, AlikeTeethAreAmbiguousModuloHalfATurn) {
  const RevolutionMatcher m = make(212.5, 2e-6, 2e-6);
  const OffsetSearch s = search_offset(m, 2);
  // Either alignment is right modulo 180 deg.
  EXPECT_LT(std::min(circular_distance_deg(s.offset_angle_deg, 212.5),
                     circular_distance_deg(s.offset_angle_deg, 32.5)),
            kNoiseFreeTolDeg)
      << s.offset_angle_deg;
  EXPECT_NEAR(circular_distance_deg(s.runner_up_deg, s.offset_angle_deg), 180.0,
              2 * kNoiseFreeTolDeg);
  EXPECT_TRUE(s.ambiguous);
  EXPECT_LT(s.runner_up_ratio, 1.1);
}

TEST(OffsetSearch, OneToothHasNoRunnerUp) {
  const RevolutionMatcher m = make(12.0, 1e-6, 0.0);
  const OffsetSearch s = search_offset(m, 1);
  EXPECT_LT(circular_distance_deg(s.offset_angle_deg, 12.0), kNoiseFreeTolDeg);
  EXPECT_TRUE(std::isnan(s.runner_up_deg));
  EXPECT_FALSE(s.ambiguous);
}

TEST(OffsetSearch, OffsetNearZeroWrapsIntoRange) {
  const RevolutionMatcher m = make(359.95, 1e-6, 4e-6);
  const OffsetSearch s = search_offset(m, 2);
  EXPECT_GE(s.offset_angle_deg, 0.0);
  EXPECT_LT(s.offset_angle_deg, 360.0);
  EXPECT_LT(circular_distance_deg(s.offset_angle_deg, 359.95), kNoiseFreeTolDeg);
}

TEST(OffsetSearch, ErrorIsTheRmsOfBothAxes) {
  // Measured = simulated + constant (dx, dy) at offset 0: E(0) = sqrt((dx^2 + dy^2) / 2).
  Eigen::VectorXd s = Eigen::VectorXd::LinSpaced(16, 0.0, 1.0);
  Eigen::VectorXd mx = s.array() + 3.0;
  Eigen::VectorXd my = s.array() - 4.0;
  const RevolutionMatcher m(mx, my, s, s);
  EXPECT_NEAR(m.rms_error_m(0.0), std::sqrt(12.5), 1e-12);
  EXPECT_NEAR(m.rms_error_m(2 * kPi), std::sqrt(12.5), 1e-12);
}

TEST(OffsetSearch, BadInputThrows) {
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(16);
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(4);
  try {
    RevolutionMatcher(a, b, a, a);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "RevolutionMatcher: measured x has 16 points, y 4: must be equal and "
                 ">= 8");
  }
  Eigen::VectorXd nan = a;
  nan[3] = std::nan("");
  EXPECT_THROW(RevolutionMatcher(a, a, nan, a), InputError);
  const RevolutionMatcher m(a, a, a, a);
  EXPECT_THROW(search_offset(m, 0), InputError);
  OffsetSearchOptions o;
  o.resolution_deg = 2.0;
  try {
    search_offset(m, 2, o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "offset.resolution_deg = 2: must be in (0, coarse_step_deg]");
  }
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
