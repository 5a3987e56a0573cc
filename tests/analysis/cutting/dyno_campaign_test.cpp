// Acceptance: a synthetic slot campaign (000 sec. 3.2: six feeds 0.025 ... 0.150 mm/tooth)
// with known coefficients from the 000 appendix goes through analyse_slot_record and
// fit_slot_coefficients and must return them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "analysis/common/constants.h"
#include "analysis/cutting/dyno_slot.h"
#include "analysis/cutting/slot_fit.h"
#include "analysis/cutting/slot_synth.h"

namespace chatterlab {
namespace cutting {
namespace {

// Acceptance tolerances of the brief. Measured errors (docs/dyno-coefficients.md) are well
// below: the mean forces are good to ~0.2 % per record, the edge terms are intercepts of a
// line extrapolated to h = 0 and so carry more of the scatter.
constexpr double kCuttingRelTol = 0.03;  // Ktc, Krc
constexpr double kEdgeRelTol = 0.15;     // Kte, Kre
constexpr double kThetaTolRad = 0.1 * kDegToRad;

struct Row {
  const char* name;
  milling::CuttingCoefficients k;
};

// 000 appendix: 6061-T6511 and 7075-T651, "30-deg Uncoated A".
const Row kRows[] = {
    {"6061-T6511 30-deg Uncoated A", {5.89e8, 3.19e8, 9.08e3, 11.3e3}},
    {"7075-T651 30-deg Uncoated A", {5.24e8, 2.26e8, 16.2e3, 16.1e3}},
};

double mod_pi_distance(double a, double b) {
  double d = std::fmod(a - b, kPi);
  if (d < 0.0) d += kPi;
  return std::min(d, kPi - d);
}

struct CampaignResult {
  SlotCoefficients fit;
  double worst_theta_rad = 0.0;
};

// Six records, one per feed, 1 mm deep, 0.5 s at 50 kHz; the same dynamometer mounting
// (theta_dyn = 0.6113 rad, not a round number) but different offsets, start angles and noise
// seeds per record. 2 N force noise (about 1/10 of the smallest mean force), 0.05 V on the
// zero-count channel. The analysis is given the nominal 9000 rpm.
CampaignResult run_campaign(const milling::CuttingCoefficients& k, const DynoOptions& options) {
  const double feeds_mm[] = {0.025, 0.050, 0.075, 0.100, 0.125, 0.150};
  const double theta_dyn = 0.6113;
  Eigen::VectorXd h(6), b(6), ft(6), fr(6);
  CampaignResult out;
  for (int i = 0; i < 6; ++i) {
    SlotRecordSpec s;
    s.coefficients = k;
    s.spindle_rpm = 8973.4;  // actual speed of a spindle set to 9000 rpm
    s.feed_per_tooth_m = feeds_mm[i] * 1e-3;
    s.depth_m = 1.0e-3;
    s.theta_dyn_rad = theta_dyn;
    s.initial_tool_angle_rad = 0.37 + 0.91 * i;
    s.offset_x_N = 12.5 - 3.1 * i;
    s.offset_y_N = -7.25 + 1.7 * i;
    s.noise_std_N = 2.0;
    s.zero_noise_std_V = 0.05;
    s.fs_hz = 50000.0;
    s.duration_s = 0.5;
    s.seed = 100 + static_cast<std::uint64_t>(i);
    const SlotRecord rec = generate_slot_record(s);
    const SlotRecordResult r =
        analyse_slot_record(rec.Fx_N, rec.Fy_N, rec.zero_V, rec.fs_hz, 9000.0, options);
    EXPECT_TRUE(r.summary.ok()) << r.summary.message;
    out.worst_theta_rad =
        std::max(out.worst_theta_rad, mod_pi_distance(r.theta_dyn_rad, theta_dyn));
    h[i] = s.feed_per_tooth_m;
    b[i] = s.depth_m;
    ft[i] = r.mean_Ft_N;
    fr[i] = r.mean_Fr_N;
  }
  out.fit = fit_slot_coefficients(h, ft, fr, b, options);
  return out;
}

TEST(DynoCampaign, RecoversAppendixCoefficients) {
  for (const Row& row : kRows) {
    const CampaignResult c = run_campaign(row.k, DynoOptions{});
    const milling::CuttingCoefficients& got = c.fit.coefficients;
    ASSERT_TRUE(c.fit.summary.ok()) << c.fit.summary.message;
    EXPECT_TRUE(c.fit.summary.warnings.empty());
    EXPECT_LT(c.worst_theta_rad, kThetaTolRad) << row.name;
    const double e_ktc = got.Kt_N_m2 / row.k.Kt_N_m2 - 1.0;
    const double e_kte = got.Kte_N_m / row.k.Kte_N_m - 1.0;
    const double e_krc = got.Kr_N_m2 / row.k.Kr_N_m2 - 1.0;
    const double e_kre = got.Kre_N_m / row.k.Kre_N_m - 1.0;
    EXPECT_LT(std::abs(e_ktc), kCuttingRelTol) << row.name;
    EXPECT_LT(std::abs(e_krc), kCuttingRelTol) << row.name;
    EXPECT_LT(std::abs(e_kte), kEdgeRelTol) << row.name;
    EXPECT_LT(std::abs(e_kre), kEdgeRelTol) << row.name;
    std::printf(
        "%s: Ktc %+.3f %%, Kte %+.3f %%, Krc %+.3f %%, Kre %+.3f %%, worst theta_dyn %.4f deg, "
        "R^2 %.6f / %.6f, RMS residual %.4f / %.4f N\n",
        row.name, 100 * e_ktc, 100 * e_kte, 100 * e_krc, 100 * e_kre, c.worst_theta_rad / kDegToRad,
        c.fit.tangential.r_squared, c.fit.radial.r_squared, c.fit.tangential.rms_residual_N,
        c.fit.radial.rms_residual_N);
  }
}

TEST(DynoCampaign, DissertationConventionGivesHalfTheCuttingCoefficients) {
  DynoOptions doc;
  doc.mean_force_model = SlotMeanForceModel::kDissertationEq3_5;
  const CampaignResult a = run_campaign(kRows[0].k, DynoOptions{});
  const CampaignResult d = run_campaign(kRows[0].k, doc);
  ASSERT_TRUE(a.fit.summary.ok());
  ASSERT_TRUE(d.fit.summary.ok());
  // Same records, same means: the convention only divides the slopes by 2 (a power of two,
  // so the halving is exact in floating point).
  EXPECT_EQ(2.0 * d.fit.coefficients.Kt_N_m2, a.fit.coefficients.Kt_N_m2);
  EXPECT_EQ(2.0 * d.fit.coefficients.Kr_N_m2, a.fit.coefficients.Kr_N_m2);
  EXPECT_EQ(d.fit.coefficients.Kte_N_m, a.fit.coefficients.Kte_N_m);
  EXPECT_EQ(d.fit.coefficients.Kre_N_m, a.fit.coefficients.Kre_N_m);
}

}  // namespace
}  // namespace cutting
}  // namespace chatterlab
