#include "analysis/cutting/slot_synth.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/signal/pulses.h"

namespace chatterlab {
namespace cutting {
namespace {

// 000 appendix, 6061-T6511, "30-deg Uncoated A".
const milling::CuttingCoefficients kAppendix{5.89e8, 3.19e8, 9.08e3, 11.3e3};

SlotRecordSpec clean_spec() {
  SlotRecordSpec s;
  s.coefficients = kAppendix;
  s.spindle_rpm = 9000.0;
  s.feed_per_tooth_m = 0.1e-3;
  s.depth_m = 1.0e-3;
  s.theta_dyn_rad = 0.6113;
  s.initial_tool_angle_rad = 1.234;
  s.fs_hz = 50000.0;
  s.duration_s = 0.1;
  return s;
}

TEST(SlotSynth, ZeroCountEdgesSitOnThePulseInstants) {
  // Ramp of 50 us = 2.5 samples at 50 kHz: mid-level interpolation is exact up to rounding of
  // the phase arithmetic (1e-9 sample).
  constexpr double kEdgeTolSamples = 1e-6;
  const SlotRecord r = generate_slot_record(clean_spec());
  const std::vector<double> e = signal::rising_edges(r.zero_V, 2.5, 0.5);
  ASSERT_EQ(e.size(), r.zero_count_times_s.size());
  ASSERT_EQ(e.size(), 15u);  // 0.1 s at 150 rev/s
  for (std::size_t k = 0; k < e.size(); ++k) {
    EXPECT_NEAR(e[k], r.zero_count_times_s[k] * r.fs_hz, kEdgeTolSamples) << k;
  }
}

TEST(SlotSynth, ZeroCountLeadsToothChangeByThetaDyn) {
  // 000 sec. 3.2 sign convention: theta_dyn = 2 pi (t_change - t_zero) / T, positive when the
  // zero-count comes first. Exact by construction, checked to rounding.
  constexpr double kTimeTol = 1e-12;
  for (double theta_dyn : {0.6113, -0.9321}) {
    SlotRecordSpec s = clean_spec();
    s.theta_dyn_rad = theta_dyn;
    const SlotRecord r = generate_slot_record(s);
    const double period = 60.0 / s.spindle_rpm;
    const double t_zero = r.zero_count_times_s.at(3);
    // Tooth change nearest to the zero-count.
    double nearest = r.tooth_change_times_s.front();
    for (double t : r.tooth_change_times_s) {
      if (std::abs(t - t_zero) < std::abs(nearest - t_zero)) nearest = t;
    }
    EXPECT_NEAR(2.0 * kPi * (nearest - t_zero) / period, theta_dyn, 2.0 * kPi * kTimeTol / period);
  }
}

TEST(SlotSynth, Eqs31And32RecoverTheForceModel) {
  // Without noise or offsets, projecting with the true theta_dyn (000 eqs 3.1-3.2) gives the
  // force model of 000 eqs 3.3-3.4 on the cutting tooth: at tool angle theta,
  // F_t = Ktc b h |sin theta| + Kte b.
  constexpr double kForceTolN = 1e-9;
  const SlotRecordSpec s = clean_spec();
  const SlotRecord r = generate_slot_record(s);
  const double omega = 2.0 * kPi * s.spindle_rpm / 60.0;
  const double c = std::cos(s.theta_dyn_rad);
  const double sn = std::sin(s.theta_dyn_rad);
  for (Eigen::Index i : {7, 100, 1234, 4999}) {
    const double theta = s.initial_tool_angle_rad + omega * static_cast<double>(i) / s.fs_hz;
    const double chip = s.feed_per_tooth_m * std::abs(std::sin(theta));
    const double ft = kAppendix.Kt_N_m2 * s.depth_m * chip + kAppendix.Kte_N_m * s.depth_m;
    const double fr = kAppendix.Kr_N_m2 * s.depth_m * chip + kAppendix.Kre_N_m * s.depth_m;
    EXPECT_NEAR(std::abs(r.Fx_N[i] * c + r.Fy_N[i] * sn), ft, kForceTolN) << i;
    EXPECT_NEAR(std::abs(-r.Fx_N[i] * sn + r.Fy_N[i] * c), fr, kForceTolN) << i;
  }
}

TEST(SlotSynth, OffsetsAndSeededNoise) {
  SlotRecordSpec s = clean_spec();
  const SlotRecord clean = generate_slot_record(s);
  s.offset_x_N = 12.5;
  s.offset_y_N = -7.25;
  s.noise_std_N = 2.0;
  s.seed = 7;
  const SlotRecord noisy = generate_slot_record(s);
  const Eigen::VectorXd dx = noisy.Fx_N - clean.Fx_N;
  const Eigen::VectorXd dy = noisy.Fy_N - clean.Fy_N;
  // 5000 samples: the mean of N(0, 2) is within 4 sigma = 4 * 2 / sqrt(5000) = 0.11 N, the
  // sample std within 4 * 2 / sqrt(2 * 5000) = 0.08 N.
  constexpr double kMeanTolN = 0.11;
  constexpr double kStdTolN = 0.08;
  EXPECT_NEAR(dx.mean(), 12.5, kMeanTolN);
  EXPECT_NEAR(dy.mean(), -7.25, kMeanTolN);
  const double sx = std::sqrt((dx.array() - dx.mean()).square().sum() / (dx.size() - 1));
  EXPECT_NEAR(sx, 2.0, kStdTolN);
  // Same seed, same record; another seed, another record.
  EXPECT_EQ(generate_slot_record(s).Fx_N, noisy.Fx_N);
  s.seed = 8;
  EXPECT_NE(generate_slot_record(s).Fx_N, noisy.Fx_N);
}

TEST(SlotSynth, RejectsBadSpec) {
  SlotRecordSpec s = clean_spec();
  s.coefficients.Kr_N_m2 = std::nan("");
  try {
    generate_slot_record(s);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "slot_record.coefficients.Kr_N_m2 = nan: must be finite");
  }
  s = clean_spec();
  s.zero_pulse_width_s = 4e-3;  // a revolution lasts 6.67 ms at 9000 rpm
  try {
    generate_slot_record(s);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "slot_record.zero_pulse_width_s + 2 zero_pulse_rise_s = 0.0041: must be "
                 "shorter than half a revolution");
  }
}

}  // namespace
}  // namespace cutting
}  // namespace chatterlab
