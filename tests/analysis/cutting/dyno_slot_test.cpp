#include "analysis/cutting/dyno_slot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/cutting/slot_synth.h"

namespace chatterlab {
namespace cutting {
namespace {

// 000 appendix, 6061-T6511, "30-deg Uncoated A".
const milling::CuttingCoefficients kAppendix{5.89e8, 3.19e8, 9.08e3, 11.3e3};

// The spindle runs at 8973.4 rpm for a 9000 rpm setting (0.3 % low, as a loaded spindle
// does): the analysis is given the nominal speed and measures the real one from the pulses.
// At this speed the sample phases of successive revolutions do not repeat, so the fold on the
// revolution phase is dense; see CommensurateSamplingLimitsThetaResolution for the case where
// they repeat.
constexpr double kNominalRpm = 9000.0;
constexpr double kActualRpm = 8973.4;

// theta_dyn accuracy with edge forces (the appendix coefficients): the tooth change is a jump
// that demodulation locates to within the gap between folded sample phases. Measured 0.010 deg
// worst on clean records and 0.036 deg worst over 30 noisy seeds (docs/dyno-coefficients.md);
// 0.1 deg is the refinement target of the brief.
constexpr double kThetaTolEdgeRad = 0.1 * kDegToRad;
// Without edge forces |D| has a flat (quadratic) peak and noise moves it: measured 0.51 deg
// worst, 0.25 deg RMS over 29 seeds at 2 N noise; 0.8 deg is about 3 RMS.
constexpr double kThetaTolNoEdgeRad = 0.8 * kDegToRad;

SlotRecordSpec base_spec() {
  SlotRecordSpec s;
  s.coefficients = kAppendix;
  s.spindle_rpm = kActualRpm;
  s.feed_per_tooth_m = 0.1e-3;
  s.depth_m = 1.0e-3;
  s.theta_dyn_rad = 0.6113;
  s.initial_tool_angle_rad = 1.234;
  s.offset_x_N = 12.5;
  s.offset_y_N = -7.25;
  s.fs_hz = 50000.0;
  s.duration_s = 0.5;
  return s;
}

// Mean |F_t|, |F_r| over a revolution for chip h |sin theta| with one tooth cutting:
// (2/pi) b Kc h + b Ke (docs/dyno-coefficients.md).
double mean_ft(const SlotRecordSpec& s) {
  return 2.0 / kPi * s.coefficients.Kt_N_m2 * s.depth_m * s.feed_per_tooth_m +
         s.coefficients.Kte_N_m * s.depth_m;
}
double mean_fr(const SlotRecordSpec& s) {
  return 2.0 / kPi * s.coefficients.Kr_N_m2 * s.depth_m * s.feed_per_tooth_m +
         s.coefficients.Kre_N_m * s.depth_m;
}

// Distance between two angles modulo pi (theta_dyn is defined modulo pi).
double mod_pi_distance(double a, double b) {
  double d = std::fmod(a - b, kPi);
  if (d < 0.0) d += kPi;
  return std::min(d, kPi - d);
}

SlotRecordResult analyse(const SlotRecord& r, double rpm, const DynoOptions& o = {}) {
  return analyse_slot_record(r.Fx_N, r.Fy_N, r.zero_V, r.fs_hz, rpm, o);
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

TEST(AnalyseSlotRecord, CleanRecordsRecoverThetaForcesAndOffsets) {
  // Mean forces: errors come from the theta_dyn error (0.01 deg = 1.8e-4 rad puts
  // F_t/F_r * 1.8e-4 = 0.03 % of F_t into |F_r|) and the sampled |sin| (measured 0.013 % on
  // |F_t|, 0.026 % on |F_r| worst); 0.1 %.
  constexpr double kMeanRelTol = 1e-3;
  // Offsets: the rotating-frame forces average zero over whole revolutions up to the
  // fractional sample at each end: 0.0036 N worst measured on forces of ~70 N peak.
  constexpr double kOffsetTolN = 0.01;
  int q = 0;
  for (double theta_dyn : {0.6113, -0.9321, 1.5512, -1.5601, 0.0137}) {
    SlotRecordSpec s = base_spec();
    s.theta_dyn_rad = theta_dyn;
    s.initial_tool_angle_rad = 0.37 + 0.91 * q++;
    const SlotRecord rec = generate_slot_record(s);
    const SlotRecordResult a = analyse(rec, kNominalRpm);
    ASSERT_TRUE(a.summary.ok()) << a.summary.message;
    EXPECT_TRUE(a.summary.warnings.empty());
    EXPECT_LT(mod_pi_distance(a.theta_dyn_rad, theta_dyn), kThetaTolEdgeRad) << theta_dyn;
    EXPECT_GT(a.theta_dyn_rad, -0.5 * kPi);
    EXPECT_LE(a.theta_dyn_rad, 0.5 * kPi);
    EXPECT_NEAR(a.mean_Ft_N / mean_ft(s), 1.0, kMeanRelTol) << theta_dyn;
    EXPECT_NEAR(a.mean_Fr_N / mean_fr(s), 1.0, kMeanRelTol) << theta_dyn;
    EXPECT_NEAR(a.offset_x_N, s.offset_x_N, kOffsetTolN);
    EXPECT_NEAR(a.offset_y_N, s.offset_y_N, kOffsetTolN);
    const int whole = static_cast<int>(rec.zero_count_times_s.size()) - 1;
    EXPECT_GE(whole, 73);  // 74.8 revolutions in 0.5 s
    EXPECT_EQ(a.revolutions, whole);
    EXPECT_EQ(a.per_revolution_Ft_N.size(), static_cast<std::size_t>(whole));
    EXPECT_NEAR(a.measured_rpm, kActualRpm, 1e-6);  // exact edges (ramped pulses)
    EXPECT_GT(a.switching_contrast, 0.95);          // measured 0.9988
  }
}

TEST(AnalyseSlotRecord, NoisyRecordsOverThirtySeeds) {
  // 2 N force noise, 0.05 V zero-count noise, theta_dyn swept over (-1.2, 1.2) rad.
  // Measured worst: theta 0.036 deg, |F_t| 0.10 %, |F_r| 0.11 %; 0.5 % bounds the mean forces.
  constexpr double kMeanRelTol = 5e-3;
  for (int seed = 1; seed <= 30; ++seed) {
    SlotRecordSpec s = base_spec();
    s.theta_dyn_rad = -1.2 + 0.08 * seed;
    s.initial_tool_angle_rad = 0.37 + 0.91 * seed;
    s.noise_std_N = 2.0;
    s.zero_noise_std_V = 0.05;
    s.seed = static_cast<std::uint64_t>(seed);
    const SlotRecordResult a = analyse(generate_slot_record(s), kNominalRpm);
    ASSERT_TRUE(a.summary.ok()) << a.summary.message;
    EXPECT_LT(mod_pi_distance(a.theta_dyn_rad, s.theta_dyn_rad), kThetaTolEdgeRad) << seed;
    EXPECT_NEAR(a.mean_Ft_N / mean_ft(s), 1.0, kMeanRelTol) << seed;
    EXPECT_NEAR(a.mean_Fr_N / mean_fr(s), 1.0, kMeanRelTol) << seed;
  }
}

TEST(AnalyseSlotRecord, WithoutEdgeForcesTheChangeIsAZeroCrossing) {
  // Kte = Kre = 0: the case 000 sec. 3.2 describes (Fx and Fy pass through zero at the
  // change). Demodulation still finds it; noise widens the error (see kThetaTolNoEdgeRad).
  for (int seed = 1; seed <= 30; ++seed) {
    SlotRecordSpec s = base_spec();
    s.coefficients.Kte_N_m = 0.0;
    s.coefficients.Kre_N_m = 0.0;
    s.theta_dyn_rad = -1.2 + 0.08 * seed;
    s.initial_tool_angle_rad = 0.37 + 0.91 * seed;
    s.noise_std_N = seed == 1 ? 0.0 : 2.0;
    s.zero_noise_std_V = 0.05;
    s.seed = static_cast<std::uint64_t>(seed);
    const SlotRecordResult a = analyse(generate_slot_record(s), kNominalRpm);
    ASSERT_TRUE(a.summary.ok()) << a.summary.message;
    const double tol = seed == 1 ? kThetaTolEdgeRad : kThetaTolNoEdgeRad;
    EXPECT_LT(mod_pi_distance(a.theta_dyn_rad, s.theta_dyn_rad), tol) << seed;
  }
}

TEST(AnalyseSlotRecord, ThetaDynIsReportedModuloPiInHalfOpenRange) {
  // 2.0 rad and 2.0 - pi = -1.1416 rad describe the same mounting (eqs 3.1-3.2 use |.|); the
  // tooth change nearest the zero-count is reported.
  SlotRecordSpec s = base_spec();
  s.theta_dyn_rad = 2.0;
  const SlotRecordResult a = analyse(generate_slot_record(s), kNominalRpm);
  ASSERT_TRUE(a.summary.ok());
  EXPECT_NEAR(a.theta_dyn_rad, 2.0 - kPi, kThetaTolEdgeRad);
}

TEST(SwitchingPhase, SquareWaveTimesConstantVector) {
  // F = s(phi) (3, 4) with s switching at 0.7 rad and 0.7 + pi, phases every 0.001 rad: the
  // plateau of equal maxima is the 0.001 rad gap holding 0.7, so the centre is within
  // 0.0005 rad; s_psi F is then a constant vector, so the contrast is 1.
  constexpr double kGapTolRad = 0.0005 + 1e-9;
  std::vector<double> phi;
  for (int k = 0; k < 6283; ++k) phi.push_back(0.0005 + 0.001 * k);
  Eigen::Matrix2Xd F(2, static_cast<Eigen::Index>(phi.size()));
  for (std::size_t k = 0; k < phi.size(); ++k) {
    const double sgn = (phi[k] >= 0.7 && phi[k] < 0.7 + kPi) ? 1.0 : -1.0;
    F.col(static_cast<Eigen::Index>(k)) = sgn * Eigen::Vector2d(3.0, 4.0);
  }
  double contrast = -1.0;
  const double psi = switching_phase_rad(phi, F, 1.0 * kDegToRad, 0.0001, &contrast);
  EXPECT_NEAR(psi, 0.7, kGapTolRad);
  EXPECT_NEAR(contrast, 1.0, 1e-12);
  // The same wave shifted by pi gives the same switching phase (modulo pi).
  const double psi2 = switching_phase_rad(phi, -F, 1.0 * kDegToRad, 0.0001);
  EXPECT_NEAR(psi2, 0.7, kGapTolRad);
}

TEST(AnalyseSlotRecord, WeakSwitchingContrastWarns) {
  // Air cut: no cutting forces, only 2 N noise. The record "succeeds" (pulses are fine) but
  // theta_dyn means nothing, and the warning says so.
  SlotRecordSpec s = base_spec();
  s.coefficients = milling::CuttingCoefficients{0.0, 0.0, 0.0, 0.0};
  s.noise_std_N = 2.0;
  const SlotRecordResult a = analyse(generate_slot_record(s), kNominalRpm);
  ASSERT_TRUE(a.summary.ok());
  EXPECT_LT(a.switching_contrast, 0.1);  // measured 0.02
  ASSERT_EQ(a.summary.warnings.size(), 1u);
  EXPECT_TRUE(starts_with(a.summary.warnings[0], "weak tooth-change signature: "))
      << a.summary.warnings[0];
}

TEST(AnalyseSlotRecord, CommensurateSamplingLimitsThetaResolution) {
  // At exactly 9000 rpm and 50 kHz a revolution is 1000/3 samples: the sample phases repeat
  // every 3 revolutions, 1000 distinct phases 0.36 deg apart. A jump between two of them is
  // located only to that gap, and the plateau centre is within half of it (0.18 deg) of the
  // truth; the documented resolution limit, not a noise effect (clean records). Where the
  // change falls in the gap depends on the start angle, hence the sweep.
  constexpr double kHalfGapRad = 0.5 * 0.36 * kDegToRad + 0.01 * kDegToRad;  // + fine-grid step
  double worst = 0.0;
  for (int k = 0; k < 20; ++k) {
    SlotRecordSpec s = base_spec();
    s.spindle_rpm = 9000.0;
    s.theta_dyn_rad = -1.3 + 0.13 * k;
    s.initial_tool_angle_rad = 0.37 + 0.91 * k;
    const SlotRecordResult a = analyse(generate_slot_record(s), 9000.0);
    ASSERT_TRUE(a.summary.ok());
    worst = std::max(worst, mod_pi_distance(a.theta_dyn_rad, s.theta_dyn_rad));
  }
  EXPECT_LT(worst, kHalfGapRad);
  EXPECT_GT(worst, kThetaTolEdgeRad);  // measured 0.17 deg: the limit is real
}

TEST(AnalyseSlotRecord, DataErrorsFailTheSummary) {
  SlotRecordSpec s = base_spec();
  s.spindle_rpm = 9000.0;  // 1000/3 samples per revolution: round numbers in the messages
  const SlotRecord good = generate_slot_record(s);

  {  // NaN samples
    SlotRecord r = good;
    r.Fy_N[1234] = std::nan("");
    r.Fy_N[2000] = std::nan("");
    const SlotRecordResult a = analyse(r, 9000.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_EQ(a.summary.message, "NaN samples in Fy_N: 2 of 25000, first at index 1234");
    EXPECT_TRUE(std::isnan(a.theta_dyn_rad));
    EXPECT_TRUE(std::isnan(a.mean_Ft_N));
  }
  {  // No zero-count edges (channel disconnected)
    SlotRecord r = good;
    r.zero_V.setZero();
    const SlotRecordResult a = analyse(r, 9000.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_EQ(a.summary.message,
              "no zero-count edges: zero_V never rises through 2.5 V after being below 2 V "
              "(max 0 V)");
  }
  {  // One whole revolution only: 12 ms at 6.67 ms per revolution, first pulse at ~4.7 ms
    SlotRecordSpec shorter = s;
    shorter.duration_s = 0.012;
    shorter.initial_tool_angle_rad = 1.234;
    const SlotRecordResult a = analyse(generate_slot_record(shorter), 9000.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_EQ(a.summary.message, "fewer than 2 whole revolutions: 1 between 2 zero-count edges");
  }
  {  // Nominal speed 6.7 % off the pulses (333.33 samples measured, 312.5 expected)
    const SlotRecordResult a = analyse(good, 9600.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_TRUE(starts_with(a.summary.message,
                            "zero-count edge spacing disagrees with spindle_rpm = 9600 by more "
                            "than 5 %: interval 0 (from sample "))
        << a.summary.message;
    EXPECT_TRUE(
        ends_with(a.summary.message, "is 333.333 samples (9000 rpm), expected 312.5 samples"))
        << a.summary.message;
  }
  {  // A spurious pulse halves one interval
    SlotRecord r = good;
    const Eigen::Index mid = static_cast<Eigen::Index>(
        0.5 * (good.zero_count_times_s[3] + good.zero_count_times_s[4]) * good.fs_hz);
    r.zero_V.segment(mid, 5).setConstant(5.0);
    const SlotRecordResult a = analyse(r, 9000.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_TRUE(starts_with(a.summary.message,
                            "zero-count edge spacing disagrees with spindle_rpm = 9000 by more "
                            "than 5 %: interval 3 "))
        << a.summary.message;
  }
  {  // Sampled too slowly: 4 kHz at 9000 rpm is 26.7 samples per revolution
    SlotRecordSpec slow = s;
    slow.fs_hz = 4000.0;
    const SlotRecordResult a = analyse(generate_slot_record(slow), 9000.0);
    EXPECT_FALSE(a.summary.ok());
    EXPECT_EQ(a.summary.message,
              "too few samples per revolution: fs_hz * 60 / spindle_rpm = 26.6667 < 36");
  }
}

TEST(AnalyseSlotRecord, BadArgumentsThrow) {
  SlotRecordSpec s = base_spec();
  s.spindle_rpm = 9000.0;
  const SlotRecord good = generate_slot_record(s);
  const Eigen::VectorXd shorter = good.Fy_N.head(100);
  try {
    analyse_slot_record(good.Fx_N, shorter, good.zero_V, good.fs_hz, 9000.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "analyse_slot_record: Fx_N has 25000 samples, Fy_N 100, zero_V 25000: must be "
                 "equal");
  }
  try {
    analyse_slot_record(good.Fx_N, good.Fy_N, good.zero_V, good.fs_hz, -1.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "analyse_slot_record: spindle_rpm = -1: must be > 0");
  }
  DynoOptions o;
  o.rpm_tolerance = 0.0;
  try {
    analyse(good, 9000.0, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "dyno.rpm_tolerance = 0: must be in (0, 1)");
  }
}

}  // namespace
}  // namespace cutting
}  // namespace chatterlab
