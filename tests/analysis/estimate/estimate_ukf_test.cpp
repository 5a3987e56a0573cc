// The unscented variants (ukf-*, ekf_variants.h) on the simulated cut of estimate_modal_test.cpp
// and estimate_coeff_test.cpp (tests/support/synthetic_cuts.h: 000 table 5.2 incline 1 at 1 mm,
// 0.2 s of data, 396,000 filter steps; 000 sec. 6.1's start values).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "analysis/common/summary.h"
#include "analysis/estimate/ekf_variants.h"
#include "tests/support/record_property.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab {
namespace estimate {
namespace {

using testing::dissertation_start_coefficients;
using testing::dissertation_start_modal;
using testing::table52_coefficients;
using testing::table52_modal;

constexpr double kMassStiffnessTolerance = 0.02;  // as the EKFs (estimate_modal_test.cpp)
constexpr double kDampingTolerance = 0.10;
// The coefficient models are linear in the state (the chip is an input): the unscented
// transform is then exact and the UKF is the EKF (which is the linear filter) up to rounding.
// Measured over 396,000 steps: at most 5.5e-11 relative on the estimates and their variances.
constexpr double kSameToRounding = 1e-8;

const MeasuredCut& cut() {
  static const MeasuredCut c = testing::synthetic_cut(testing::SyntheticCutSpec{});
  return c;
}

void expect_same(const EkfResult& ukf, const EkfResult& ekf) {
  ASSERT_TRUE(ukf.summary.ok()) << ukf.summary.message;
  ASSERT_TRUE(ekf.summary.ok()) << ekf.summary.message;
  ASSERT_EQ(ukf.estimates.size(), ekf.estimates.size());
  EXPECT_EQ(ukf.steps, ekf.steps);
  double worst = 0.0;
  for (std::size_t j = 0; j < ekf.estimates.size(); ++j) {
    const Estimate& u = ukf.estimates[j];
    const Estimate& e = ekf.estimates[j];
    EXPECT_EQ(u.key, e.key);
    EXPECT_NEAR(u.value, e.value, kSameToRounding * std::abs(e.value)) << e.key;
    EXPECT_NEAR(u.variance, e.variance, kSameToRounding * e.variance) << e.key;
    worst = std::max(
        {worst, std::abs(u.value / e.value - 1.0), std::abs(u.variance / e.variance - 1.0)});
  }
  EXPECT_NEAR(ukf.nis.mean, ekf.nis.mean, kSameToRounding * ekf.nis.mean);
  testing::record_and_print(ukf.estimator + "_vs_ekf_max_relative_difference", worst);
}

TEST(UkfCoeff, EqualsTheEkfOnTheLinearCoefficientModel) {
  const EkfResult ukf =
      ekf_coeff(EstimatorId::kUkfCoeffXy, cut(), CutSetup{}, {table52_modal(), {{2e9, 1e9}}});
  const EkfResult ekf =
      ekf_coeff(EstimatorId::kCoeffXy, cut(), CutSetup{}, {table52_modal(), {{2e9, 1e9}}});
  EXPECT_EQ(ukf.estimator, "ukf-coeff-xy");
  expect_same(ukf, ekf);
}

TEST(UkfCoeff, PerToothEqualsTheEkfPerTooth) {
  const CoeffEkfInputs in{table52_modal(), dissertation_start_coefficients()};
  const EkfResult ukf = ekf_coeff(EstimatorId::kUkfCoeffXyPerTooth, cut(), CutSetup{}, in);
  const EkfResult ekf = ekf_coeff(EstimatorId::kCoeffXyPerTooth, cut(), CutSetup{}, in);
  expect_same(ukf, ekf);
  // And so it meets the coefficient filters' 2 % (estimate_coeff_test.cpp).
  const auto truth = table52_coefficients();
  EXPECT_NEAR(ukf.value("Kt2_N_m2") / truth[1].Kt_N_m2, 1.0, 0.02);
  EXPECT_NEAR(ukf.value("Kr2_N_m2") / truth[1].Kr_N_m2, 1.0, 0.02);
}

// The modal model is nonlinear (k x / m, c v / m): the UKF differs from the EKF, and recovers
// the truth within the EKFs' acceptance from 000 sec. 6.1's start (m -28 %, c +83 %, k +18 %).
TEST(UkfModal, RecoversAllThreeFromTheDissertationStart) {
  const ModalParameters t = table52_modal();
  for (EstimatorId id : {EstimatorId::kUkfModalX, EstimatorId::kUkfModalXy}) {
    const EkfResult r =
        ekf_modal(id, cut(), CutSetup{}, {table52_coefficients(), dissertation_start_modal()});
    ASSERT_TRUE(r.summary.ok()) << r.estimator << ": " << r.summary.message;
    const std::string n = r.estimator;
    testing::record_and_print(n + "_m_error_pct", 100 * (r.value("m_kg") / t.m_kg - 1));
    testing::record_and_print(n + "_c_error_pct", 100 * (r.value("c_kg_s") / t.c_kg_s - 1));
    testing::record_and_print(n + "_k_error_pct", 100 * (r.value("k_N_m") / t.k_N_m - 1));
    testing::record_and_print(n + "_runtime_s", r.runtime_s);
    testing::record_and_print(n + "_mean_nis", r.nis.mean);
    EXPECT_NEAR(r.value("m_kg") / t.m_kg, 1.0, kMassStiffnessTolerance) << n;
    EXPECT_NEAR(r.value("k_N_m") / t.k_N_m, 1.0, kMassStiffnessTolerance) << n;
    EXPECT_NEAR(r.value("c_kg_s") / t.c_kg_s, 1.0, kDampingTolerance) << n;
    EXPECT_EQ(r.steps, 396000);
  }
}

TEST(UkfModal, HeldParameterVariantsWithTheTrueHeldValue) {
  // ukf-modal-xy-mk holds c, ukf-modal-xy-mc holds k: each at the truth, from 000 sec. 6.1's
  // start for the others.
  const ModalParameters t = table52_modal();
  for (EstimatorId id : {EstimatorId::kUkfModalXyMk, EstimatorId::kUkfModalXyMc}) {
    const bool mk = id == EstimatorId::kUkfModalXyMk;
    ModalParameters start = dissertation_start_modal();
    (mk ? start.c_kg_s : start.k_N_m) = mk ? t.c_kg_s : t.k_N_m;
    const EkfResult r = ekf_modal(id, cut(), CutSetup{}, {table52_coefficients(), start});
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    EXPECT_NEAR(r.value("m_kg") / t.m_kg, 1.0, kMassStiffnessTolerance) << r.estimator;
    if (mk) {
      EXPECT_NEAR(r.value("k_N_m") / t.k_N_m, 1.0, kMassStiffnessTolerance);
    } else {
      EXPECT_NEAR(r.value("c_kg_s") / t.c_kg_s, 1.0, kDampingTolerance);
    }
  }
}

// A start damping of 0 is allowed (ModalEkfInputs): the UKF spreads it as 1 % damping instead
// of giving P0 a zero variance (no square root: the run would stop at its first step).
TEST(UkfModal, ZeroStartDampingStillRuns) {
  const ModalParameters t = table52_modal();
  ModalParameters start = dissertation_start_modal();
  start.c_kg_s = 0.0;
  const EkfResult r =
      ekf_modal(EstimatorId::kUkfModalXy, cut(), CutSetup{}, {table52_coefficients(), start});
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  testing::record_and_print("ukf_zero_start_c_error_pct", 100 * (r.value("c_kg_s") / t.c_kg_s - 1));
  testing::record_and_print("ukf_zero_start_m_error_pct", 100 * (r.value("m_kg") / t.m_kg - 1));
  EXPECT_NEAR(r.value("m_kg") / t.m_kg, 1.0, kMassStiffnessTolerance);
  EXPECT_NEAR(r.value("k_N_m") / t.k_N_m, 1.0, kMassStiffnessTolerance);
  // c starts 34 of its standard deviations (0.65 kg/s) below the truth and gets to -9.5 % in the
  // 0.2 s: within 15 %, short of the 10 % acceptance from this narrow prior.
  EXPECT_NEAR(r.value("c_kg_s") / t.c_kg_s, 1.0, 0.15);
}

// The initial parameter spread must keep every sigma point's mass positive: the 7-state points
// reach sqrt(7) standard deviations, so the relative sd must stay below 1 / sqrt(7) = 0.378.
TEST(UkfModal, InitialSpreadThatWouldGiveANegativeMassIsRefused) {
  ModalEkfOptions o;
  o.ukf_p0_relative_sd = 0.4;
  try {
    ekf_modal(EstimatorId::kUkfModalXy, cut(), CutSetup{},
              {table52_coefficients(), dissertation_start_modal()}, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ekf.ukf_p0_relative_sd = 0.4: must be > 0 and below "
                                         "1 / sqrt(alpha^2 (7 + kappa)) = 0.377964"),
              std::string::npos)
        << e.what();
  }
  o = ModalEkfOptions{};
  o.ukf.kappa = -6.0;
  EXPECT_THROW(ekf_modal(EstimatorId::kUkfModalX, cut(), CutSetup{},
                         {table52_coefficients(), dissertation_start_modal()}, o),
               InputError);
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
