// The cut-record generator (cut_synth.h) against its definition: tip deflections from a second
// run of the simulator, sensors = tip / sensor_to_tip + contour exactly without noise, the
// tachometer's edges at theta_1 = offset through the tachometer step, noise of the stated size.
#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/milling/simulation.h"
#include "analysis/sync/cut_synth.h"
#include "analysis/sync/tach_angle.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace sync {
namespace {

constexpr double kFs = 100000.0;
constexpr double kRpm = 15000.0;
constexpr int kP = 400;             // samples per revolution at kFs, kRpm
constexpr double kExactRad = 1e-9;  // tach phase from exact two-sample ramps (tach_angle_test)
// Sensor metres: sums of terms of 1e-5 m rounded to double (and the tip's float trace, which
// enters both sides alike).
constexpr double kExactM = 1e-18;

CutRecordSpec quiet_spec() {
  CutRecordSpec s = testing::sync_test_cut();
  s.cut.depth = milling::DepthProfile::constant(1e-3, 20);
  s.air_revolutions = 5;
  s.noise_tip_m = 0.0;
  return s;
}

TEST(CutSynth, SensorsAreTipOverSensorToTipPlusTheContour) {
  const CutRecordSpec s = quiet_spec();
  const CutRecord r = synthesize_cut_record(s);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_EQ(r.samples_per_revolution, kP);
  EXPECT_EQ(r.cut_revolutions, 20);
  ASSERT_EQ(r.x_sensor_m.size(), (5 + 20 + 2) * kP);
  // Second method: the simulator's own trace, every 4th step (1,600 steps a revolution).
  milling::RecordingRequest rq;
  rq.trace_revolutions = 20;
  const milling::SimulationResult sim = milling::simulate(s.cut, rq);
  ASSERT_TRUE(sim.summary.ok());
  for (Eigen::Index i = 0; i < r.x_sensor_m.size(); ++i) {
    const Eigen::Index k = i - 5 * kP;
    const bool cutting = k >= 0 && k < 20 * kP;
    const double tip_x = cutting ? sim.trace.x_m[static_cast<std::size_t>(4 * k)] : 0.0;
    const double tip_y = cutting ? sim.trace.y_m[static_cast<std::size_t>(4 * k)] : 0.0;
    ASSERT_EQ(r.x_tip_m[i], tip_x) << i;
    ASSERT_EQ(r.y_tip_m[i], tip_y) << i;
    const double theta = kTwoPi * static_cast<double>(i % kP) / kP;
    ASSERT_NEAR(r.x_sensor_m[i], tip_x / 2.78 + s.contour.x_m(theta), kExactM) << i;
    ASSERT_NEAR(r.y_sensor_m[i], tip_y / 2.78 + s.contour.y_m(theta), kExactM) << i;
    ASSERT_NEAR(r.theta1_rad[i], kTwoPi * static_cast<double>(i) / kP, 1e-12);
  }
  // Windows: air from 0 to 4 revolutions, the cut from 5 to 25 (4 ms each).
  EXPECT_NEAR(r.air_end_s, 4 * 0.004, 1e-15);
  EXPECT_NEAR(r.cut_start_s, 5 * 0.004, 1e-15);
  EXPECT_NEAR(r.cut_end_s, 25 * 0.004, 1e-15);
  EXPECT_EQ(r.depth_start_m, 1e-3);
  EXPECT_EQ(r.depth_end_m, 1e-3);
  EXPECT_EQ(r.harmonic_phase_rad, s.contour.harmonic_phase_rad);
}

TEST(CutSynth, TachometerEdgesFallWhereTheta1IsTheOffset) {
  const CutRecordSpec s = quiet_spec();
  const CutRecord r = synthesize_cut_record(s);
  const TachAngle t = tach_angle(r.tach_V, kFs, kRpm);
  ASSERT_TRUE(t.summary.ok()) << t.summary.message;
  EXPECT_EQ(t.edges.size(), 27u);  // one per revolution
  const Eigen::VectorXd theta = theta1_rad(t, s.offset_angle_deg);
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    double d = std::fmod(theta[i] - r.theta1_rad[i], kTwoPi);
    if (d < 0) d += kTwoPi;
    ASSERT_LT(std::min(d, kTwoPi - d), kExactRad) << i;
  }
}

TEST(CutSynth, TachVoltsRampsAcrossTheEdge) {
  // 400 samples per turn, edge at 1 rad: half level on the instant, full one sample after,
  // none one sample before; the pulse falls 20 samples later.
  const double spr = kP / kTwoPi;
  EXPECT_NEAR(tach_volts(1.0, 1.0, spr, 20.0), 2.5, 1e-12);
  EXPECT_NEAR(tach_volts(1.0 + 1.0 / spr, 1.0, spr, 20.0), 5.0, 1e-12);
  EXPECT_NEAR(tach_volts(1.0 - 1.0 / spr, 1.0, spr, 20.0), 0.0, 1e-12);
  EXPECT_NEAR(tach_volts(1.0 + 20.0 / spr, 1.0, spr, 20.0), 2.5, 1e-9);
  EXPECT_NEAR(tach_volts(1.0 + 22.0 / spr + kTwoPi, 1.0, spr, 20.0), 0.0, 1e-9);
}

TEST(CutSynth, ContourIsItsFormula) {
  ToolContour c;
  c.eccentricity_m = 3e-6;
  c.eccentricity_angle_rad = 0.7;
  c.harmonic_m = {1e-6};
  c.harmonic_phase_rad = {0.3};
  // theta_1 = 0: c_x = e sin a + A cos(pi + phi), c_y = e cos a + A cos(phi).
  EXPECT_NEAR(c.x_m(0.0), 3e-6 * std::sin(0.7) - 1e-6 * std::cos(0.3), 1e-20);
  EXPECT_NEAR(c.y_m(0.0), 3e-6 * std::cos(0.7) + 1e-6 * std::cos(0.3), 1e-20);
  // Fixed in the tool: one turn later the same.
  EXPECT_NEAR(c.x_m(1.3 + kTwoPi), c.x_m(1.3), 1e-20);
}

TEST(CutSynth, NoiseHasTheStatedSizeAndDrawnPhasesFollowTheSeed) {
  CutRecordSpec s = quiet_spec();
  s.noise_tip_m = 5e-7;
  s.contour.harmonic_phase_rad.clear();  // drawn from the seed
  const CutRecord r = synthesize_cut_record(s);
  ASSERT_EQ(r.harmonic_phase_rad.size(), 3u);
  for (double p : r.harmonic_phase_rad) {
    EXPECT_GE(p, 0.0);
    EXPECT_LT(p, kTwoPi);
  }
  ToolContour used = s.contour;
  used.harmonic_phase_rad = r.harmonic_phase_rad;
  double ss = 0.0;
  for (Eigen::Index i = 0; i < r.x_sensor_m.size(); ++i) {
    const double theta = kTwoPi * static_cast<double>(i % kP) / kP;
    const double n = (r.x_sensor_m[i] - used.x_m(theta)) * 2.78 - r.x_tip_m[i];
    ss += n * n;
  }
  // 10,800 samples: the RMS of white noise lies within 3 % of sigma (4.4 standard deviations).
  EXPECT_NEAR(std::sqrt(ss / static_cast<double>(r.x_sensor_m.size())) / 5e-7, 1.0, 0.03);
  // Same seed, same record; another seed, other phases.
  const CutRecord again = synthesize_cut_record(s);
  EXPECT_EQ(again.x_sensor_m, r.x_sensor_m);
  s.seed += 1;
  EXPECT_NE(synthesize_cut_record(s).harmonic_phase_rad, r.harmonic_phase_rad);
}

TEST(CutSynth, StepsPerToothPutASampleOnEveryKthStep) {
  EXPECT_EQ(sampled_steps_per_tooth(400, 2), 800);         // S = 1600 = 4 P
  EXPECT_EQ(sampled_steps_per_tooth(400, 3), 800);         // S = 2400 = 6 P, 3 teeth
  EXPECT_EQ(sampled_steps_per_tooth(250, 2), 875);         // S = 1750 = 7 P, even
  EXPECT_EQ(sampled_steps_per_tooth(400, 2, 2000), 2000);  // S = 4000 = 10 P
}

TEST(CutSynth, BadSpecsNameTheField) {
  CutRecordSpec s = quiet_spec();
  s.fs_hz = 99999.0;
  try {
    synthesize_cut_record(s);
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "cut_record.fs_hz * 60 / spindle_rpm = 399.996: must be a whole number of samples "
                 "per revolution (>= 16)");
  }
  s = quiet_spec();
  s.cut.steps_per_tooth = 700;  // 1,400 steps: not a multiple of 400
  EXPECT_THROW(synthesize_cut_record(s), InputError);
  s = quiet_spec();
  s.contour.harmonic_phase_rad = {0.1};
  EXPECT_THROW(synthesize_cut_record(s), InputError);
}

TEST(CutSynth, DivergingRunFailsTheSummary) {
  CutRecordSpec s = quiet_spec();
  s.cut.switching = milling::SwitchingRule::kAngleOnly;  // 000 sec. 2.2 taken literally
  s.cut.depth = milling::DepthProfile::constant(10e-3, 200);
  const CutRecord r = synthesize_cut_record(s);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message.rfind("simulation failed: deflection left the tool radius", 0), 0u)
      << r.summary.message;
  EXPECT_EQ(r.x_sensor_m.size(), 0);
}

}  // namespace
}  // namespace sync
}  // namespace chatterlab
