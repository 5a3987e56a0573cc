// The modal fit's model: its value against 003 eq. 4-27 and its Jacobian against central
// differences (CONVENTIONS.md: every analytic Jacobian against finite differences).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/frf/modal_model.h"
#include "analysis/frf/mode.h"

namespace chatterlab {
namespace frf {
namespace {

ModalModel two_modes_with_residuals() {
  ModalModel m;
  m.wn0.resize(2);
  m.zeta0.resize(2);
  m.a0.resize(2);
  m.wn0 << kTwoPi * 891.8, kTwoPi * 2500.0;
  m.zeta0 << 0.063, 0.02;
  m.a0 << 1.0 / 0.03134, -1.0 / 0.05;
  m.residual_scale = 1e-6;
  m.w_ref = kTwoPi * 400.0;
  return m;
}

TEST(ModalModel, ValueIsTheModalSumPlusResiduals) {
  constexpr double kRelTol = 1e-13;  // rounding
  const ModalModel model = two_modes_with_residuals();
  // theta: mode 1 at its scales, mode 2 with wn x1.01, zeta x0.9, A x1.2; r_U = 0.3, r_L = 0.2.
  const std::vector<double> theta = {0.0, 0.0, 1.0, std::log(1.01), std::log(0.9), 1.2, 0.3, 0.2};
  const std::vector<Mode> modes = {mode_from_modal(891.8, 0.063, 0.03134),
                                   mode_from_modal(2500.0 * 1.01, 0.02 * 0.9, 0.05 / 1.2)};
  for (double f : {100.0, 891.8, 1700.0, 2525.0, 6000.0}) {
    Eigen::VectorXd fv(1);
    fv << f;
    const double w = kTwoPi * f;
    // Mode 2 has a negative modal constant: receptance() of a positive mass, negated.
    const Eigen::VectorXcd h1 = receptance({modes[0]}, fv);
    const Eigen::VectorXcd h2 = receptance({modes[1]}, fv);
    const std::complex<double> expected =
        h1[0] - h2[0] + 1e-6 * (0.3 - 0.2 * std::pow(kTwoPi * 400.0 / w, 2));
    const std::complex<double> value = model.evaluate(theta.data(), w);
    EXPECT_LT(std::abs(value - expected), kRelTol * std::abs(expected)) << f;
  }
}

TEST(ModalModel, JacobianMatchesCentralDifferences) {
  // Central differences with step 1e-6 on O(1) parameters: truncation ~1e-12, rounding
  // ~1e-10 relative; 1e-6 of the largest entry is a safe bound.
  constexpr double kStep = 1e-6;
  constexpr double kRelTol = 1e-6;
  const ModalModel model = two_modes_with_residuals();
  const std::vector<double> theta = {0.01, -0.05, 0.9, -0.02, 0.1, 1.1, 0.3, -0.4};
  const int np = model.parameters();
  ASSERT_EQ(np, 8);
  for (double f : {300.0, 880.0, 900.0, 2480.0, 2600.0}) {
    const double w = kTwoPi * f;
    std::vector<std::complex<double>> J_h_theta(static_cast<size_t>(np));
    model.evaluate(theta.data(), w, J_h_theta.data());
    double largest = 0.0;
    for (const auto& j : J_h_theta) largest = std::max(largest, std::abs(j));
    for (int p = 0; p < np; ++p) {
      std::vector<double> plus = theta, minus = theta;
      plus[static_cast<size_t>(p)] += kStep;
      minus[static_cast<size_t>(p)] -= kStep;
      const std::complex<double> numeric =
          (model.evaluate(plus.data(), w) - model.evaluate(minus.data(), w)) / (2.0 * kStep);
      EXPECT_LT(std::abs(numeric - J_h_theta[static_cast<size_t>(p)]), kRelTol * largest)
          << "f = " << f << " Hz, parameter " << p;
    }
  }
}

}  // namespace
}  // namespace frf
}  // namespace chatterlab
