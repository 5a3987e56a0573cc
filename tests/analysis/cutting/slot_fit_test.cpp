#include "analysis/cutting/slot_fit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace cutting {
namespace {

// Straight-line data fitted by OLS: exact up to rounding of sums of ~10 terms.
constexpr double kExactRelTol = 1e-9;

// 000 appendix, 6061-T6511, "30-deg Uncoated A".
const milling::CuttingCoefficients kAppendix{5.89e8, 3.19e8, 9.08e3, 11.3e3};

struct Campaign {
  Eigen::VectorXd h, b, ft, fr;
};

// Mean magnitudes from the closed form mean|F| = c b Kc h + b Ke at the document's feeds
// (000 sec. 3.2: 0.025 ... 0.150 mm/tooth), depths alternating 1.0 and 1.5 mm.
Campaign closed_form(double c) {
  Campaign k;
  k.h.resize(6);
  k.h << 0.025e-3, 0.050e-3, 0.075e-3, 0.100e-3, 0.125e-3, 0.150e-3;
  k.b.resize(6);
  k.b << 1.0e-3, 1.5e-3, 1.0e-3, 1.5e-3, 1.0e-3, 1.5e-3;
  k.ft = k.b.cwiseProduct(c * kAppendix.Kt_N_m2 * k.h +
                          Eigen::VectorXd::Constant(6, kAppendix.Kte_N_m));
  k.fr = k.b.cwiseProduct(c * kAppendix.Kr_N_m2 * k.h +
                          Eigen::VectorXd::Constant(6, kAppendix.Kre_N_m));
  return k;
}

TEST(FitSlotCoefficients, ExactLinesGiveTheCoefficients) {
  const Campaign k = closed_form(2.0 / kPi);
  const SlotCoefficients r = fit_slot_coefficients(k.h, k.ft, k.fr, k.b);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_TRUE(r.summary.warnings.empty());
  EXPECT_EQ(r.records, 6);
  EXPECT_EQ(r.distinct_feeds, 6);
  EXPECT_EQ(r.mean_force_model, SlotMeanForceModel::kSingleToothChip);
  EXPECT_NEAR(r.coefficients.Kt_N_m2 / 5.89e8, 1.0, kExactRelTol);
  EXPECT_NEAR(r.coefficients.Kte_N_m / 9.08e3, 1.0, kExactRelTol);
  EXPECT_NEAR(r.coefficients.Kr_N_m2 / 3.19e8, 1.0, kExactRelTol);
  EXPECT_NEAR(r.coefficients.Kre_N_m / 11.3e3, 1.0, kExactRelTol);
  EXPECT_NEAR(r.tangential.r_squared, 1.0, 1e-12);
  EXPECT_LT(r.tangential.rms_residual_N, 1e-9);
  // The fitted line reproduces a point for plotting: slope = (2/pi) Ktc, 000 eq 3.7 / b.
  EXPECT_NEAR(r.tangential.force_N(0.1e-3, 1.5e-3) / k.ft[3], 1.0, kExactRelTol);
  EXPECT_NEAR(r.tangential.slope_N_per_m2 / (2.0 / kPi * 5.89e8), 1.0, kExactRelTol);
}

TEST(FitSlotCoefficients, DissertationConventionHalvesCuttingTerms) {
  // Same data: 000 eqs 3.9/3.11 (pi slope / 4b) give exactly half of pi slope / 2b; the edge
  // terms (eqs 3.10/3.12) do not depend on the convention.
  const Campaign k = closed_form(2.0 / kPi);
  DynoOptions doc;
  doc.mean_force_model = SlotMeanForceModel::kDissertationEq3_5;
  const SlotCoefficients a = fit_slot_coefficients(k.h, k.ft, k.fr, k.b);
  const SlotCoefficients d = fit_slot_coefficients(k.h, k.ft, k.fr, k.b, doc);
  ASSERT_TRUE(d.summary.ok());
  EXPECT_EQ(d.coefficients.Kt_N_m2 * 2.0, a.coefficients.Kt_N_m2);
  EXPECT_EQ(d.coefficients.Kr_N_m2 * 2.0, a.coefficients.Kr_N_m2);
  EXPECT_EQ(d.coefficients.Kte_N_m, a.coefficients.Kte_N_m);
  EXPECT_EQ(d.coefficients.Kre_N_m, a.coefficients.Kre_N_m);
  // And on data made by eq 3.5 as printed (4/pi), that convention returns its coefficients.
  const Campaign printed = closed_form(4.0 / kPi);
  const SlotCoefficients p =
      fit_slot_coefficients(printed.h, printed.ft, printed.fr, printed.b, doc);
  EXPECT_NEAR(p.coefficients.Kt_N_m2 / 5.89e8, 1.0, kExactRelTol);
  EXPECT_NEAR(p.coefficients.Kr_N_m2 / 3.19e8, 1.0, kExactRelTol);
  EXPECT_DOUBLE_EQ(mean_force_slope_factor(SlotMeanForceModel::kSingleToothChip), 2.0 / kPi);
  EXPECT_DOUBLE_EQ(mean_force_slope_factor(SlotMeanForceModel::kDissertationEq3_5), 4.0 / kPi);
}

TEST(FitSlotCoefficients, ResidualAndRSquaredByHand) {
  // h = 0.1, 0.2, 0.3 mm, b = 1 mm, F = 10, 30, 20 N -> y = F/b = 1e4, 3e4, 2e4 N/m.
  // OLS: slope = sum(dh dy) / sum(dh^2) = (1e-4 * 1e4) / 2e-8 = 5e7 N/m^2,
  //      intercept = 2e4 - 5e7 * 2e-4 = 1e4 N/m; residuals b(y - line) = -5, 10, -5 N,
  //      RMS = sqrt(150 / 3) = 7.0710678 N; R^2 = 1 - 1.5e8 / 2e8 = 0.25.
  Eigen::VectorXd h(3), b(3), f(3);
  h << 0.1e-3, 0.2e-3, 0.3e-3;
  b << 1e-3, 1e-3, 1e-3;
  f << 10.0, 30.0, 20.0;
  const SlotCoefficients r = fit_slot_coefficients(h, f, f, b);
  ASSERT_TRUE(r.summary.ok());
  EXPECT_NEAR(r.tangential.slope_N_per_m2 / 5e7, 1.0, kExactRelTol);
  EXPECT_NEAR(r.tangential.intercept_N_per_m / 1e4, 1.0, kExactRelTol);
  EXPECT_NEAR(r.tangential.rms_residual_N, std::sqrt(50.0), 1e-9);
  EXPECT_NEAR(r.tangential.r_squared, 0.25, 1e-12);
  EXPECT_NEAR(r.coefficients.Kt_N_m2 / (kPi * 5e7 / 2.0), 1.0, kExactRelTol);
  ASSERT_EQ(r.summary.warnings.size(), 2u);  // both lines (same data)
  EXPECT_EQ(r.summary.warnings[0],
            "tangential line: R^2 = 0.25 < 0.95: mean force is not linear in feed");
}

TEST(FitSlotCoefficients, NegativeInterceptWarns) {
  Eigen::VectorXd h(2), b(2), ft(2), fr(2);
  h << 0.05e-3, 0.10e-3;
  b << 1e-3, 1e-3;
  ft << 10.0, 30.0;  // line through (0.05 mm, 10 N), (0.1 mm, 30 N): intercept -10 N at b = 1 mm
  fr << 10.0, 15.0;
  const SlotCoefficients r = fit_slot_coefficients(h, ft, fr, b);
  ASSERT_TRUE(r.summary.ok());
  ASSERT_EQ(r.summary.warnings.size(), 1u);
  EXPECT_EQ(r.summary.warnings[0],
            "tangential line: negative edge coefficient -10000 N/m (the intercept should be >= 0)");
}

TEST(FitSlotCoefficients, FewerThanTwoDistinctFeedsFails) {
  Eigen::VectorXd h(3), b(3), f(3);
  h << 0.1e-3, 0.1e-3, 0.1e-3;
  b << 1e-3, 2e-3, 3e-3;
  f << 10.0, 20.0, 30.0;
  const SlotCoefficients r = fit_slot_coefficients(h, f, f, b);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_EQ(r.summary.message,
            "fewer than 2 distinct feeds: 1 among 3 records; a line in feed needs at least 2 "
            "(000 eqs 3.7-3.8)");
  EXPECT_TRUE(std::isnan(r.coefficients.Kt_N_m2));
  const Eigen::VectorXd none;
  EXPECT_EQ(fit_slot_coefficients(none, none, none, none).summary.message,
            "fewer than 2 distinct feeds: 0 among 0 records; a line in feed needs at least 2 "
            "(000 eqs 3.7-3.8)");
}

TEST(FitSlotCoefficients, BadInputThrows) {
  Eigen::VectorXd h(2), b(2), f(2), f3(3);
  h << 0.05e-3, 0.10e-3;
  b << 1e-3, 0.0;
  f << 10.0, 20.0;
  f3 << 1.0, 2.0, 3.0;
  try {
    fit_slot_coefficients(h, f, f, b);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "fit_slot_coefficients: depth_m[1] = 0: must be > 0");
  }
  try {
    fit_slot_coefficients(h, f, f3, h);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "fit_slot_coefficients: feeds_m has 2 entries, mean_Ft_N 2, mean_Fr_N 3, "
                 "depth_m 2: must be equal");
  }
}

}  // namespace
}  // namespace cutting
}  // namespace chatterlab
