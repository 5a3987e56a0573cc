#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/common/constants.h"
#include "analysis/sync/cut_synth.h"
#include "analysis/sync/tip_deflection.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace sync {
namespace {

constexpr double kFs = 100000.0;
constexpr double kRpm = 15000.0;

double rms(const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); }

// The 000 sec. 5.2 cut at 1 mm with table 5.2 incline-1 parameters, 3 um eccentricity plus
// three harmonics at the sensor, 5e-7 m noise at the tip, sensor_to_tip 2.78.
class TipDeflectionOnSyntheticCut : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    spec_ = new CutRecordSpec(testing::sync_test_cut());
    cut_ = new CutRecord(testing::make_cut(*spec_));
  }
  static void TearDownTestSuite() {
    delete cut_;
    delete spec_;
  }
  static CutRecordSpec* spec_;
  static CutRecord* cut_;
};
CutRecordSpec* TipDeflectionOnSyntheticCut::spec_ = nullptr;
CutRecord* TipDeflectionOnSyntheticCut::cut_ = nullptr;

TEST_F(TipDeflectionOnSyntheticCut, ContourRemovedToWithinNoiseOverSqrtNAir) {
  const TachAngle tach = tach_angle(cut_->tach_V, kFs, kRpm);
  ASSERT_TRUE(tach.summary.ok()) << tach.summary.message;
  const TipDeflection d = tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach,
                                         spec_->sensor_to_tip, cut_->air_start_s, cut_->air_end_s);
  ASSERT_TRUE(d.summary.ok()) << d.summary.message;
  // Air window [0, 11 T] with the edge at 0.41 T: revolutions 0..9 lie inside.
  EXPECT_EQ(d.contour.revolutions.count, 10);
  EXPECT_EQ(d.contour.phase_rad.size(), 400);
  const int n_air = d.contour.revolutions.count;

  // The estimated contour against the true tip contour sensor_to_tip * c(theta_1) at
  // theta_1 = phi + offset. Each grid point interpolates two neighbouring samples with weights
  // 1 - f, f (f: the fractional part of the edge positions, the same in every revolution here),
  // then averages n_air revolutions: the error's standard deviation is
  // sigma sqrt(((1 - f)^2 + f^2) / n_air). Over 400 points the largest of 800 Gaussian deviates
  // stays below 4 standard deviations (probability of exceeding it 0.05); the RMS lies within
  // 15 % of its expectation (chi-square with 800 degrees of freedom: 3 standard deviations of
  // its 5 % spread).
  const double f = tach.edges[0] - std::floor(tach.edges[0]);
  const double weights = std::sqrt((1 - f) * (1 - f) + f * f);
  const double sigma_mean = spec_->noise_tip_m * weights / std::sqrt(n_air);
  const double offset = spec_->offset_angle_deg * kPi / 180.0;
  double worst = 0.0;
  double ss = 0.0;
  for (Eigen::Index j = 0; j < d.contour.phase_rad.size(); ++j) {
    const double theta = d.contour.phase_rad[j] + offset;
    const double ex = d.contour.x_m[j] - spec_->sensor_to_tip * spec_->contour.x_m(theta);
    const double ey = d.contour.y_m[j] - spec_->sensor_to_tip * spec_->contour.y_m(theta);
    worst = std::max({worst, std::abs(ex), std::abs(ey)});
    ss += ex * ex + ey * ey;
  }
  const double contour_rms_error = std::sqrt(ss / (2.0 * d.contour.phase_rad.size()));
  EXPECT_LT(worst, 4.0 * sigma_mean);
  EXPECT_NEAR(contour_rms_error / sigma_mean, 1.0, 0.15);
  std::printf(
      "contour: RMS error %.3g m = %.3f of its expectation %.3g m, worst %.3g m (N_air = "
      "%d, f = %.3f)\n",
      contour_rms_error, contour_rms_error / sigma_mean, sigma_mean, worst, n_air, f);

  // Air residual: white noise minus its own mean over the air revolutions,
  // sigma sqrt(1 - 1/n_air) (within 3 % for 4000 samples: 2 % is 2.8 standard deviations).
  const double expected_residual = spec_->noise_tip_m * std::sqrt(1.0 - 1.0 / n_air);
  EXPECT_NEAR(d.air_residual_rms_x_m / expected_residual, 1.0, 0.03);
  EXPECT_NEAR(d.air_residual_rms_y_m / expected_residual, 1.0, 0.03);

  // The deflection during the cut is recovered: processed minus true tip deflection is the
  // noise plus the contour error, between sigma and sigma sqrt(1 + 1/n_air) in RMS (3 % margin
  // for 48,000 samples: 2 % is 4.4 standard deviations of the RMS).
  const auto i0 = static_cast<Eigen::Index>(cut_->cut_start_s * kFs);
  const auto len = static_cast<Eigen::Index>((cut_->cut_end_s - cut_->cut_start_s) * kFs);
  const Eigen::VectorXd ex = d.x_m.segment(i0, len) - cut_->x_tip_m.segment(i0, len);
  const Eigen::VectorXd ey = d.y_m.segment(i0, len) - cut_->y_tip_m.segment(i0, len);
  const double upper = spec_->noise_tip_m * std::sqrt(1.0 + 1.0 / n_air) * 1.03;
  const double lower = spec_->noise_tip_m * 0.97;
  for (double e : {rms(ex), rms(ey)}) {
    EXPECT_GT(e, lower);
    EXPECT_LT(e, upper);
  }
  // ... while the contour alone is 2.78 * 3 um at the tip, 17 times the noise.
  EXPECT_GT(rms(d.contour.x_m), 10.0 * spec_->noise_tip_m);
  std::printf("cut: residual RMS x %.3g m, y %.3g m (noise %.3g m); deflection RMS x %.3g m\n",
              rms(ex), rms(ey), spec_->noise_tip_m, rms(cut_->x_tip_m.segment(i0, len)));
}

TEST_F(TipDeflectionOnSyntheticCut, ShortAirWindowFails) {
  const TachAngle tach = tach_angle(cut_->tach_V, kFs, kRpm);
  ASSERT_TRUE(tach.summary.ok());
  // [0, 1.5 T] holds the revolution from edge 0 (0.41 T) to edge 1 (1.41 T) only.
  const TipDeflection d =
      tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach, 2.78, 0.0, 0.006);
  EXPECT_FALSE(d.summary.ok());
  EXPECT_EQ(d.summary.message,
            "air window too short: air_window_s = [0, 0.006] holds 1 whole tachometer "
            "revolution (between rising edges), need at least 2 for the runout contour");
  EXPECT_EQ(d.x_m.size(), 0);
}

TEST_F(TipDeflectionOnSyntheticCut, FailedTachometerFailsTheStep) {
  const TachAngle tach = tach_angle(Eigen::VectorXd::Zero(cut_->tach_V.size()), kFs, kRpm);
  const TipDeflection d = tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach, 2.78, 0.0, 0.04);
  EXPECT_FALSE(d.summary.ok());
  EXPECT_EQ(d.summary.message,
            "no tachometer angle: no tachometer edges: the tach channel is flat at 0 V");
}

TEST_F(TipDeflectionOnSyntheticCut, NanInTheAirWindowFails) {
  const TachAngle tach = tach_angle(cut_->tach_V, kFs, kRpm);
  Eigen::VectorXd x = cut_->x_sensor_m;
  x[1000] = std::nan("");
  const TipDeflection d = tip_deflection(x, cut_->y_sensor_m, tach, 2.78, 0.0, 0.044);
  EXPECT_FALSE(d.summary.ok());
  EXPECT_EQ(d.summary.message,
            "runout contour not finite: NaN or infinite x or y samples between t = 0.00163667 "
            "and 0.0416367 s (the air revolutions)");
}

TEST_F(TipDeflectionOnSyntheticCut, BadArgumentsThrow) {
  const TachAngle tach = tach_angle(cut_->tach_V, kFs, kRpm);
  try {
    tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach, -2.78, 0.0, 0.04);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "tip_deflection: sensor_to_tip = -2.78: must be finite and > 0");
  }
  EXPECT_THROW(tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach, 2.78, 0.04, 0.0),
               InputError);
  EXPECT_THROW(tip_deflection(cut_->x_sensor_m.head(10), cut_->y_sensor_m, tach, 2.78, 0.0, 0.04),
               InputError);
  ContourOptions o;
  o.min_air_revolutions = 1;
  try {
    tip_deflection(cut_->x_sensor_m, cut_->y_sensor_m, tach, 2.78, 0.0, 0.04, o);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "contour.min_air_revolutions = 1: must be >= 2");
  }
}

TEST(TipDeflection, ContourFollowsADriftingSpeed) {
  // Air only, the speed rising 3 % over 20 revolutions, no noise. Every revolution is
  // resampled by its own length, so the contour is the true one up to
  //  - the interpolation error of the samples and of the grid, each at most max|c''| / 8 in
  //    sample units: sum over the terms of a h^2 (2 pi / 400)^2 / 8 = 2.78 * 13 um * 3.1e-5
  //    = 1.1e-9 m, doubled: 2.2e-9 m;
  //  - the chord error of the tach phase (linear between edges while theta_1 is a parabola:
  //    at most 7.9e-4 rad, sync_tach_angle_test) times the contour's slope at the tip,
  //    max|c'| <= 2.78 sum a h = 2.78 * 6.6 um: 1.45e-8 m.
  // Without the per-revolution stretch the contour would be smeared by 3 % of a revolution
  // over the record (~0.5 um at the tip).
  const ToolContour contour = testing::sync_test_cut().contour;
  const double offset = 1.1;
  const int revs = 20;
  const double P = 400.0;
  const auto n = static_cast<Eigen::Index>(revs * P);
  const double omega0 = 2 * kPi / P;
  const double a = 0.03 / static_cast<double>(n);
  Eigen::VectorXd xs(n), ys(n), tach(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = static_cast<double>(i);
    const double theta = omega0 * (x + 0.5 * a * x * x);
    xs[i] = contour.x_m(theta);
    ys[i] = contour.y_m(theta);
    tach[i] = tach_volts(theta, offset, 1.0 / (omega0 * (1 + a * x)), 20.0);
  }
  const TachAngle t = tach_angle(tach, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  const TipDeflection d = tip_deflection(xs, ys, t, 2.78, 0.0, n / kFs);
  ASSERT_TRUE(d.summary.ok()) << d.summary.message;
  EXPECT_EQ(d.contour.revolutions.count, t.revolutions);  // the window spans the record
  const double bound = 2.2e-9 + 1.45e-8;
  // The residual between the first and last edge: the same two errors, once for the contour
  // and once for the sample's own phase.
  const double residual_bound = 2.0 * bound;
  double worst_contour = 0.0;
  for (Eigen::Index j = 0; j < d.contour.phase_rad.size(); ++j) {
    const double theta = d.contour.phase_rad[j] + offset;
    worst_contour = std::max({worst_contour, std::abs(d.contour.x_m[j] - 2.78 * contour.x_m(theta)),
                              std::abs(d.contour.y_m[j] - 2.78 * contour.y_m(theta))});
  }
  EXPECT_LT(worst_contour, bound);
  const auto i0 = static_cast<Eigen::Index>(std::ceil(t.edges.front()));
  const auto i1 = static_cast<Eigen::Index>(std::floor(t.edges.back()));
  const double worst_residual = std::max(d.x_m.segment(i0, i1 - i0).cwiseAbs().maxCoeff(),
                                         d.y_m.segment(i0, i1 - i0).cwiseAbs().maxCoeff());
  EXPECT_LT(worst_residual, residual_bound);
  std::printf("drift: contour error %.3g m (bound %.3g), residual %.3g m (bound %.3g)\n",
              worst_contour, bound, worst_residual, residual_bound);
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
