// One modal-parameter type and one cutting-coefficient type: the modal form against closed
// forms, and the former copies are the same types (or, for frf::Mode, one of them).
#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

#include "analysis/common/constants.h"
#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/frf/mode.h"
#include "analysis/milling/force_model.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace {

static_assert(std::is_same_v<milling::AxisModal, ModalParameters>);
static_assert(std::is_base_of_v<ModalParameters, frf::Mode>);
static_assert(std::is_same_v<milling::CuttingCoefficients, CuttingCoefficients>);
static_assert(std::is_same_v<estimate::ToothCoefficients, CuttingCoefficients>);

constexpr double kRel = 1e-14;  // a few roundings of sqrt, products and quotients

TEST(ModalParameters, ModalFormOfAKnownMode) {
  // k = m (2 pi fn)^2 and c = 2 zeta sqrt(k m) for fn = 897 Hz, zeta = 0.036, m = 0.032 kg.
  const double m = 0.032, fn = 897.0, zeta = 0.036;
  const double k = m * std::pow(kTwoPi * fn, 2);
  const ModalParameters p{m, 2.0 * zeta * std::sqrt(k * m), k};
  EXPECT_NEAR(natural_frequency_hz(p), fn, kRel * fn);
  EXPECT_NEAR(damping_ratio(p), zeta, kRel * zeta);
}

TEST(ModalParameters, TheTapTestsModeIsTheSameModel) {
  // frf::Mode's fn and zeta are these functions of its m, c, k (000 sec. 5.1's hammer values).
  const frf::Mode mode = frf::mode_from_mck(0.03211, 13.39, 1.023e6);
  const ModalParameters& p = mode;  // a Mode is used wherever modal parameters are
  EXPECT_EQ(natural_frequency_hz(p), mode.fn_hz);
  EXPECT_EQ(damping_ratio(p), mode.zeta);
  EXPECT_EQ(p.k_N_m, 1.023e6);
}

TEST(ModalParameters, NothingIsMadeUp) {
  const ModalParameters p;
  EXPECT_TRUE(std::isnan(p.m_kg));
  EXPECT_TRUE(std::isnan(p.c_kg_s));
  EXPECT_TRUE(std::isnan(p.k_N_m));
}

TEST(CuttingCoefficients, ATwoValueToothHasNoEdgeForce) {
  // {Kt, Kr}: 000 eqs 2.1-2.2 (edge terms 0); the cutting terms stay NaN until given.
  const CuttingCoefficients tooth{2.483e8, 2.196e8};
  EXPECT_EQ(tooth.Kte_N_m, 0.0);
  EXPECT_EQ(tooth.Kre_N_m, 0.0);
  EXPECT_TRUE(std::isnan(CuttingCoefficients{}.Kt_N_m2));
  // The dynamometer's values without their edge terms (000 sec. 5.1).
  const CuttingCoefficients dyno{5.89e8, 3.19e8, 9.08e3, 11.3e3};
  const CuttingCoefficients cut = without_edge_terms(dyno);
  EXPECT_EQ(cut.Kt_N_m2, 5.89e8);
  EXPECT_EQ(cut.Kr_N_m2, 3.19e8);
  EXPECT_EQ(cut.Kte_N_m, 0.0);
  EXPECT_EQ(cut.Kre_N_m, 0.0);
  // The force model reads the same fields: F_t = Kt b w + Kte b (000 eqs 3.3-3.4).
  const milling::ToothForce f = milling::tooth_force(dyno, 1e-4, 1e-3, true);
  EXPECT_NEAR(f.tangential_N, 5.89e8 * 1e-3 * 1e-4 + 9.08e3 * 1e-3, 1e-12);
  EXPECT_NEAR(f.radial_N, 3.19e8 * 1e-3 * 1e-4 + 11.3e3 * 1e-3, 1e-12);
}

}  // namespace
}  // namespace chatterlab
