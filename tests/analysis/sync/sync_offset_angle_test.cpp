#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analysis/sync/cut_synth.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/tip_deflection.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace sync {
namespace {

constexpr double kFs = 100000.0;
constexpr double kRpm = 15000.0;

double circular_distance_deg(double a, double b, double period = 360.0) {
  double d = std::fmod(a - b, period);
  if (d < 0) d += period;
  return std::min(d, period - d);
}

// The whole chain on a synthetic record (testing::measured_revolution: the last 20
// revolutions), then the offset search with `model`.
OffsetAngleResult run_chain(const CutRecordSpec& spec, const milling::SimulationOptions& model,
                            RevolutionMean* measured_out = nullptr) {
  const testing::MeasuredRevolution measured = testing::measured_revolution(spec, 20);
  if (measured_out != nullptr) *measured_out = measured.mean;
  return find_offset_angle(measured.mean, model, measured.depth_m);
}

void report(const char* name, const OffsetAngleResult& r, double truth) {
  std::printf(
      "%s: offset %.4f deg (truth %.4f), RMS error %.3g m (relative %.4f), runner-up %.3f deg "
      "ratio %.3f, ambiguous %d, settle change %.2g, simulation %.2f ms, search %.2f ms\n",
      name, r.search.offset_angle_deg, truth, r.search.rms_error_m, r.relative_error,
      r.search.runner_up_deg, r.search.runner_up_ratio, r.search.ambiguous ? 1 : 0, r.settle_change,
      1e3 * r.simulation_runtime_s, 1e3 * r.search_runtime_s);
}

// Offset accuracy asked by the brief. Measured over 12 offsets and noise seeds
// (docs/cut-processing.md): worst 0.018 deg with unequal teeth, 0.063 deg (modulo 180) alike.
constexpr double kOffsetTolDeg = 0.5;

TEST(OffsetAngle, UnequalTeethOffsetIsUnique) {
  // Table 5.2 incline 1 (tooth 2 cuts 27 times harder), 1 mm, 147.3 deg.
  const CutRecordSpec spec = testing::sync_test_cut();
  RevolutionMean measured;
  const OffsetAngleResult r = run_chain(spec, spec.cut, &measured);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("unequal", r, spec.offset_angle_deg);
  EXPECT_LT(circular_distance_deg(r.search.offset_angle_deg, spec.offset_angle_deg), kOffsetTolDeg);
  EXPECT_TRUE(r.summary.warnings.empty());
  EXPECT_FALSE(r.model_teeth_alike);
  // The other half turn is far worse: the teeth are told apart.
  EXPECT_FALSE(r.search.ambiguous);
  EXPECT_GT(r.search.runner_up_ratio, 10.0);
  EXPECT_LT(circular_distance_deg(r.search.runner_up_deg, r.search.offset_angle_deg + 180.0), 45.0);
  // Same model as the data: the error left is the noise of the 20-revolution mean plus the
  // contour error, about sigma sqrt(1/20 + 1/10) = 1.9e-7 m, well under 5 % of the signal.
  EXPECT_LT(r.search.rms_error_m, 2.5e-7);
  EXPECT_LT(r.relative_error, 0.05);
  EXPECT_LT(r.settle_change, 1e-3);
  // The error curve for the figure, and its minimum at the reported offset.
  ASSERT_EQ(r.search.error_m.size(), 360);
  EXPECT_LE(r.search.rms_error_m, r.search.error_m.minCoeff());
  // The synchronized revolution: the measurement at tach phase theta_1 - offset against the
  // simulation at theta_1; their RMS difference is the search error (same grid, same shift).
  ASSERT_EQ(r.theta1_deg.size(), measured.x_m.size());
  EXPECT_EQ(r.theta1_deg[0], 0.0);
  const Eigen::VectorXd dx = r.measured_x_m - r.simulated_x_m;
  const Eigen::VectorXd dy = r.measured_y_m - r.simulated_y_m;
  const double sync_rms = std::sqrt((dx.squaredNorm() + dy.squaredNorm()) / (2.0 * dx.size()));
  // The synchronized measurement is the measured revolution interpolated once more (at
  // theta_1 - offset, between grid points with weights 1 - f, f), which scales white noise by
  // sqrt((1 - f)^2 + f^2) in [0.71, 1]: the error here is mostly that noise.
  EXPECT_LE(sync_rms, 1.01 * r.search.rms_error_m);
  EXPECT_GE(sync_rms, 0.7 * r.search.rms_error_m);
  EXPECT_EQ(r.measured_revolutions.count, 20);
}

TEST(OffsetAngle, AlikeTeethOffsetIsDefinedModuloHalfATurn) {
  CutRecordSpec spec = testing::sync_test_cut();
  const milling::DepthProfile depth = spec.cut.depth;
  spec.cut = testing::hammer_and_dynamometer();
  spec.cut.depth = depth;
  spec.offset_angle_deg = 212.5;
  const OffsetAngleResult r = run_chain(spec, spec.cut);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("alike", r, spec.offset_angle_deg);
  EXPECT_TRUE(r.model_teeth_alike);
  // Reported in [0, 180): 212.5 - 180.
  EXPECT_GE(r.search.offset_angle_deg, 0.0);
  EXPECT_LT(r.search.offset_angle_deg, 180.0);
  EXPECT_LT(std::abs(r.search.offset_angle_deg - 32.5), kOffsetTolDeg);
  EXPECT_TRUE(r.search.ambiguous);
  EXPECT_NEAR(r.search.runner_up_deg, r.search.offset_angle_deg + 180.0, 0.01);
  EXPECT_NEAR(r.search.runner_up_ratio, 1.0, 1e-3);
  ASSERT_EQ(r.summary.warnings.size(), 1u);
  EXPECT_NE(r.summary.warnings[0].find("the other tooth alignment fits almost as well"),
            std::string::npos)
      << r.summary.warnings[0];
}

TEST(OffsetAngle, HammerAndDynamometerModelOnTable52Data) {
  // 000 sec. 5.1's situation: the data come from the table 5.2 parameters (unequal teeth), the
  // search uses the hammer-test modal parameters and the dynamometer coefficients (alike
  // teeth). 000 sec. 5.2: the offset so found was "only a degree or so different" from the one
  // found with the identified parameters. Measured here: 1.2 deg, modulo 180 deg since the
  // model's teeth are alike; 3 deg allows "a degree or so".
  const CutRecordSpec spec = testing::sync_test_cut();
  const OffsetAngleResult r = run_chain(spec, testing::hammer_and_dynamometer());
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("mismatched", r, spec.offset_angle_deg);
  EXPECT_LT(circular_distance_deg(r.search.offset_angle_deg, spec.offset_angle_deg, 180.0), 3.0);
  EXPECT_TRUE(r.search.ambiguous);
  // The fit is poor (000: "significantly smaller" simulated deflections), yet it places the
  // tooth passes.
  EXPECT_GT(r.relative_error, 0.5);
}

TEST(OffsetAngle, RampComparedAtADepthBand) {
  // Incline 0.5 to 1.5 mm at 1,290 revolutions per mm (000 sec. 5.2), compared around 1 mm:
  // 21 revolutions span 0.016 mm.
  CutRecordSpec spec = testing::sync_test_cut();
  spec.cut.depth = milling::DepthProfile::ramp(0.5e-3, 1.5e-3, 1290.0);
  spec.offset_angle_deg = 303.7;
  const CutRecord cut = testing::make_cut(spec);
  const TachAngle tach = tach_angle(cut.tach_V, kFs, kRpm);
  ASSERT_TRUE(tach.summary.ok()) << tach.summary.message;
  const TipDeflection d = tip_deflection(cut.x_sensor_m, cut.y_sensor_m, tach, spec.sensor_to_tip,
                                         cut.air_start_s, cut.air_end_s);
  ASSERT_TRUE(d.summary.ok()) << d.summary.message;
  const CutSchedule schedule{cut.cut_start_s, cut.cut_end_s, cut.depth_start_m, cut.depth_end_m};
  const ComparisonWindow w = comparison_window(schedule, kRpm, 20, 1e-3);
  EXPECT_NEAR(w.depth_m, 1e-3, 1e-12);
  const RevolutionRange range = whole_revolutions_in(tach, w.start_s, w.end_s);
  EXPECT_EQ(range.count, 20);
  const RevolutionMean measured = mean_revolution(d.x_m, d.y_m, tach, range, 400);
  const OffsetAngleResult r = find_offset_angle(measured, spec.cut, w.depth_m);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  report("ramp", r, spec.offset_angle_deg);
  EXPECT_LT(circular_distance_deg(r.search.offset_angle_deg, spec.offset_angle_deg), kOffsetTolDeg);
  EXPECT_FALSE(r.search.ambiguous);
}

TEST(ComparisonWindow, ConstantDepthTakesTheLastRevolutions) {
  const double T = 0.004;  // 15,000 rpm
  const ComparisonWindow w = comparison_window({0.048, 0.288, 1e-3, 1e-3}, kRpm, 20);
  EXPECT_NEAR(w.end_s, 0.288 - T, 1e-12);
  EXPECT_NEAR(w.start_s, 0.288 - 22 * T, 1e-12);
  EXPECT_EQ(w.depth_m, 1e-3);
}

TEST(ComparisonWindow, RampCentresOnTheDepthAndStaysInside) {
  const CutSchedule ramp{1.0, 3.0, 0.0, 2e-3};  // 1 mm per second
  const ComparisonWindow w = comparison_window(ramp, kRpm, 9, 1e-3);
  EXPECT_NEAR(0.5 * (w.start_s + w.end_s), 2.0, 1e-12);
  EXPECT_NEAR(w.end_s - w.start_s, 10 * 0.004, 1e-12);
  EXPECT_NEAR(w.depth_m, 1e-3, 1e-12);
  // At the ramp's start the window is pushed one revolution inside the cut.
  const ComparisonWindow first = comparison_window(ramp, kRpm, 9, 0.0);
  EXPECT_NEAR(first.start_s, 1.004, 1e-12);
  EXPECT_NEAR(ramp.depth_at_m(5.0), 2e-3, 1e-15);  // clamped
}

TEST(ComparisonWindow, BadRequestsThrowWithTheRule) {
  const CutSchedule ramp{1.0, 3.0, 0.0, 2e-3};
  try {
    comparison_window(ramp, kRpm, 9, 2.5e-3);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "comparison_window: depth 2.5 mm: must lie within the ramp's depths [0, 2] mm");
  }
  try {
    comparison_window({0.0, 0.05, 1e-3, 1e-3}, kRpm, 20);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "comparison_window: 20 revolutions (+1, and one at each end) do not fit in "
                 "cut_window_s = [0, 0.05] at 15000 rpm");
  }
  EXPECT_THROW(comparison_window({1.0, 0.5, 1e-3, 1e-3}, kRpm, 20), InputError);
  EXPECT_THROW(comparison_window(ramp, kRpm, 0, 1e-3), InputError);
}

TEST(OffsetAngle, DivergingSimulationFailsTheStep) {
  // With the switching rule of 000 sec. 2.2 taken literally (a negative chip pulls), the
  // table 5.2 system at 10 mm grows without bound: the simulator stops it, the step fails.
  milling::SimulationOptions model = testing::table52_incline1();
  model.switching = milling::SwitchingRule::kAngleOnly;
  RevolutionMean measured;
  measured.x_m = Eigen::VectorXd::Zero(400);
  measured.y_m = Eigen::VectorXd::Zero(400);
  const OffsetAngleResult r = find_offset_angle(measured, model, 10e-3);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message.rfind("simulation at 10 mm failed: ", 0), 0u) << r.summary.message;
}

// Deflection channels of zeros or of a constant (a sensor not connected): every angle fits
// equally, so no offset is found and the step fails with the reason (issue 16: a cut with zero
// deflection was reported "ok" with an offset).
TEST(OffsetAngle, FlatMeasuredRevolutionFailsTheStep) {
  for (const double level : {0.0, 2.5e-4}) {
    RevolutionMean measured;
    measured.x_m = Eigen::VectorXd::Constant(400, level);
    measured.y_m = Eigen::VectorXd::Constant(400, -level);
    const OffsetAngleResult r = find_offset_angle(measured, testing::table52_incline1(), 1e-3);
    EXPECT_FALSE(r.summary.ok()) << level;
    // About its mean: 0 m, or round-off of the constant (1.6e-19 m).
    EXPECT_EQ(r.summary.message.rfind("the measured deflection does not vary over the revolution "
                                      "(RMS about its mean ",
                                      0),
              0u)
        << r.summary.message;
    EXPECT_NE(r.summary.message.find(" m, below 0.1 % of the simulated revolution's "),
              std::string::npos)
        << r.summary.message;
  }
}

TEST(OffsetAngle, BadArgumentsThrow) {
  RevolutionMean measured;
  measured.x_m = Eigen::VectorXd::Zero(400);
  measured.y_m = Eigen::VectorXd::Zero(400);
  try {
    find_offset_angle(measured, testing::table52_incline1(), 0.0);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "find_offset_angle: depth_m = 0: must be finite and > 0");
  }
  OffsetSearchOptions o;
  o.simulated_revolutions = 1;
  EXPECT_THROW(find_offset_angle(measured, testing::table52_incline1(), 1e-3, o), InputError);
  milling::SimulationOptions bad = testing::table52_incline1();
  bad.coefficients.pop_back();
  EXPECT_THROW(find_offset_angle(measured, bad, 1e-3), InputError);
  measured.y_m.resize(10);
  EXPECT_THROW(find_offset_angle(measured, testing::table52_incline1(), 1e-3), InputError);
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
