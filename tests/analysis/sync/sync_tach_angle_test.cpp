#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/sync/cut_synth.h"
#include "analysis/sync/tach_angle.h"

namespace chatterlab {
namespace sync {
namespace {

constexpr double kFs = 100000.0;
constexpr double kRpm = 15000.0;
constexpr double kP = 400.0;  // samples per revolution at kFs, kRpm

// Two-sample ramps centred on the edge instant: linear interpolation at mid-level is exact, so
// the phase is exact up to rounding.
constexpr double kExactRad = 1e-9;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// theta_1 of a constant speed record, tach edge at theta_1 = offset.
Eigen::VectorXd constant_speed_tach(Eigen::Index n, double offset_rad, Eigen::VectorXd* theta) {
  Eigen::VectorXd v(n);
  theta->resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    (*theta)[i] = 2 * kPi * static_cast<double>(i) / kP;
    v[i] = tach_volts((*theta)[i], offset_rad, kP / (2 * kPi), 20.0);
  }
  return v;
}

double wrapped_distance(double a, double b) {
  const double d = wrap_phase_rad(a - b);
  return std::min(d, 2 * kPi - d);
}

TEST(TachAngle, ConstantSpeedPhaseIsThetaMinusOffsetEverywhere) {
  const double offset = 212.5 * kPi / 180.0;
  Eigen::VectorXd theta;
  const Eigen::VectorXd v =
      constant_speed_tach(static_cast<Eigen::Index>(10.5 * kP), offset, &theta);
  const TachAngle t = tach_angle(v, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  EXPECT_EQ(t.revolutions, 9);  // edges in revolutions 0..9 (first at 0.59 rev), 10 edges
  EXPECT_NEAR(t.measured_rpm, kRpm, 1e-6);
  EXPECT_NEAR(t.threshold_V, 2.5, 1e-12);  // midway between the 0 V and 5 V levels
  EXPECT_NEAR(t.hysteresis_V, 0.5, 1e-12);
  // Including the extrapolated stretches before the first and after the last edge.
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    ASSERT_LT(wrapped_distance(t.phase_rad[i], theta[i] - offset), kExactRad) << i;
  }
  // theta1_rad puts the offset back.
  const Eigen::VectorXd th = theta1_rad(t, 212.5);
  for (Eigen::Index i = 0; i < v.size(); i += 37) {
    EXPECT_LT(wrapped_distance(th[i], theta[i]), kExactRad) << i;
    EXPECT_GE(th[i], 0.0);
    EXPECT_LT(th[i], 2 * kPi);
  }
}

TEST(TachAngle, UnwrappedThetaIncreasesWithTheTrueAngle) {
  // theta1_unwrapped_rad: theta_1 starting in [0, 2 pi) at sample 0 and rising by the true
  // angle's increments across every wrap (ten revolutions at constant speed).
  const double offset = 212.5 * kPi / 180.0;
  Eigen::VectorXd theta;
  const Eigen::VectorXd v =
      constant_speed_tach(static_cast<Eigen::Index>(10.5 * kP), offset, &theta);
  const TachAngle t = tach_angle(v, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  const Eigen::VectorXd u = theta1_unwrapped_rad(t, 212.5);
  ASSERT_EQ(u.size(), v.size());
  EXPECT_GE(u[0], 0.0);
  EXPECT_LT(u[0], 2 * kPi);
  EXPECT_LT(wrapped_distance(u[0], theta[0]), kExactRad);
  for (Eigen::Index i = 1; i < u.size(); ++i) {
    ASSERT_NEAR(u[i] - u[0], theta[i] - theta[0], kExactRad) << i;
  }
}

TEST(TachAngle, FollowsThreePercentSpeedDrift) {
  // Speed rising linearly by 3 % over 30 revolutions: omega(i) = omega0 (1 + a i). Between two
  // edges the phase is interpolated linearly, so its error is the chord error of a parabola:
  // at most (theta'' / 8) L^2 = omega0 a L^2 / 8 for an interval of L samples, i.e.
  // 2 pi (0.03 / 30) / 8 = 7.9e-4 rad per revolution at L = P. Extrapolated ends err by up to
  // 2 pi (0.001) (one revolution of the speed change, taken linearly) = 6.3e-3 rad.
  const int revs = 30;
  const auto n = static_cast<Eigen::Index>(revs * kP);
  const double omega0 = 2 * kPi / kP;  // rad per sample
  const double a = 0.03 / static_cast<double>(n);
  const double offset = 147.3 * kPi / 180.0;
  Eigen::VectorXd theta(n), v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    theta[i] = omega0 * (x + 0.5 * a * x * x);
    v[i] = tach_volts(theta[i], offset, 1.0 / (omega0 * (1 + a * x)), 20.0);
  }
  const TachAngle t = tach_angle(v, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  const double chord_bound = 2 * kPi * (0.03 / revs) / 8.0;
  const double end_bound = 2 * kPi * (0.03 / revs);
  double worst_inside = 0.0;
  double worst_ends = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double err = wrapped_distance(t.phase_rad[i], theta[i] - offset);
    const double p = static_cast<double>(i);
    if (p >= t.edges.front() && p <= t.edges.back()) {
      worst_inside = std::max(worst_inside, err);
    } else {
      worst_ends = std::max(worst_ends, err);
    }
  }
  EXPECT_LT(worst_inside, chord_bound);
  EXPECT_LT(worst_ends, end_bound);
  // Mean speed of the whole revolutions: within the drift of the record.
  EXPECT_GT(t.min_rpm, kRpm * 0.999);
  EXPECT_LT(t.max_rpm, kRpm * 1.031);
  EXPECT_GT(t.max_rpm / t.min_rpm, 1.025);  // the drift is seen revolution by revolution
  std::printf("drift: worst phase error %.3g rad inside (bound %.3g), %.3g rad at the ends\n",
              worst_inside, chord_bound, worst_ends);
}

TEST(TachAngle, NoisyPulseWithOddLevelsGivesOneEdgePerRevolution) {
  // 0.4 / 4.6 V levels, 0.1 V noise: the default threshold is midway (2.5 V) and the hysteresis
  // 0.42 V keeps the noise on the edges from doubling them.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  const auto n = static_cast<Eigen::Index>(8 * kP);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double theta = 2 * kPi * static_cast<double>(i) / kP;
    v[i] = 0.4 + 4.2 / 5.0 * tach_volts(theta, 1.0, kP / (2 * kPi), 20.0) + noise(rng);
  }
  const TachAngle t = tach_angle(v, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  EXPECT_EQ(t.edges.size(), 8u);
  // Levels are medians: within a few noise standard deviations / sqrt(count).
  EXPECT_NEAR(t.low_V, 0.4, 0.01);
  EXPECT_NEAR(t.high_V, 4.6, 0.05);
  EXPECT_NEAR(t.threshold_V, 2.5, 0.03);
}

TEST(TachAngle, GivenThresholdIsUsed) {
  Eigen::VectorXd theta;
  const Eigen::VectorXd v = constant_speed_tach(static_cast<Eigen::Index>(4 * kP), 0.5, &theta);
  TachOptions o;
  o.threshold_V = 1.25;  // a quarter up the ramp: the edge is half a sample earlier
  const TachAngle t = tach_angle(v, kFs, kRpm, o);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  EXPECT_EQ(t.threshold_V, 1.25);
  const double expected_edge = 0.5 / (2 * kPi) * kP - 0.5;  // ramp: 2.5 V per sample
  EXPECT_NEAR(t.edges[0], expected_edge, 1e-9);
}

TEST(TachAngle, FlatChannelHasNoEdges) {
  const TachAngle t = tach_angle(Eigen::VectorXd::Constant(1000, 0.2), kFs, kRpm);
  EXPECT_FALSE(t.summary.ok());
  EXPECT_EQ(t.summary.message, "no tachometer edges: the tach channel is flat at 0.2 V");
  EXPECT_EQ(t.phase_rad.size(), 0);
}

TEST(TachAngle, ThresholdAboveThePulseHasNoEdges) {
  Eigen::VectorXd theta;
  const Eigen::VectorXd v = constant_speed_tach(static_cast<Eigen::Index>(4 * kP), 0.5, &theta);
  TachOptions o;
  o.threshold_V = 7.0;
  const TachAngle t = tach_angle(v, kFs, kRpm, o);
  EXPECT_FALSE(t.summary.ok());
  EXPECT_EQ(t.summary.message,
            "no tachometer edges: tach never rises through 7 V after being below 6.5 V (levels "
            "0 and 5 V, 1600 samples)");
}

TEST(TachAngle, SingleEdgeIsTooFew) {
  Eigen::VectorXd theta;
  const Eigen::VectorXd v = constant_speed_tach(300, 0.5, &theta);  // 0.75 revolution
  const TachAngle t = tach_angle(v, kFs, kRpm);
  EXPECT_FALSE(t.summary.ok());
  EXPECT_EQ(t.summary.message,
            "fewer than 2 tachometer edges: one edge at t = 0.00031831 s; a revolution needs "
            "two");
}

TEST(TachAngle, SpeedMismatchNamesMeasuredAndExpectedRpm) {
  // The spindle turns at 15,000 rpm but test.yaml says 16,000 (6.7 % off).
  Eigen::VectorXd theta;
  const Eigen::VectorXd v = constant_speed_tach(static_cast<Eigen::Index>(5 * kP), 0.5, &theta);
  const TachAngle t = tach_angle(v, kFs, 16000.0);
  EXPECT_FALSE(t.summary.ok());
  EXPECT_EQ(t.summary.message,
            "tachometer speed disagrees with spindle_rpm: revolution 0 (edges at t = "
            "0.00031831 and 0.00431831 s) measures 15000 rpm, expected 16000 rpm (more than 5 % "
            "apart; 4 of 4 revolutions off: a missed or spurious pulse, or a wrong spindle_rpm)");
  EXPECT_NEAR(t.measured_rpm, 15000.0, 1e-6);
}

TEST(TachAngle, MissedPulseIsASpeedMismatch) {
  Eigen::VectorXd theta;
  Eigen::VectorXd v = constant_speed_tach(static_cast<Eigen::Index>(6 * kP), 0.5, &theta);
  // Blank the third pulse: revolution 1 spans two revolutions (7500 rpm).
  for (Eigen::Index i = static_cast<Eigen::Index>(2 * kP); i < static_cast<Eigen::Index>(3 * kP);
       ++i) {
    v[i] = 0.0;
  }
  const TachAngle t = tach_angle(v, kFs, kRpm);
  EXPECT_FALSE(t.summary.ok());
  EXPECT_TRUE(contains(t.summary.message,
                       "revolution 1 (edges at t = 0.00431831 and "
                       "0.0123183 s) measures 7500 rpm, expected 15000 rpm"))
      << t.summary.message;
}

TEST(TachAngle, BadArgumentsThrow) {
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(10);
  EXPECT_THROW(tach_angle(v, 0.0, kRpm), InputError);
  EXPECT_THROW(tach_angle(v, kFs, -1.0), InputError);
  TachOptions o;
  o.rpm_tolerance = 2.0;
  try {
    tach_angle(v, kFs, kRpm, o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "tach.rpm_tolerance = 2: must be in (0, 1)");
  }
  o = TachOptions{};
  o.hysteresis_fraction = 0.5;
  EXPECT_THROW(tach_angle(v, kFs, kRpm, o), InputError);
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
