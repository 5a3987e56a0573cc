// The receptance model the modal fit adjusts, in the scaled parameters it works with.
#pragma once

#include <Eigen/Core>
#include <complex>

namespace chatterlab {
namespace frf {

// H(w) = sum_i A_i / (wn_i^2 - w^2 + 2 j zeta_i wn_i w)           (003 eq. 4-27, A_i = 1/m_i)
//        + s (r_U - r_L (w_ref / w)^2)                            (residual terms)
// The residual terms stand for modes outside the fitted band: those above act as a
// constant compliance r_U s, those below as a mass line -r_L s w_ref^2 / w^2 (Ewins'
// upper and lower residuals, real-valued).
// Parameters theta (what the optimiser sees, all O(1) at the start):
//   theta[3i]   = ln(wn_i / wn0_i)    theta[3i+1] = ln(zeta_i / zeta0_i)
//   theta[3i+2] = A_i / A0_i          theta[3n], theta[3n+1] = r_U, r_L (if residuals)
// Log parameters keep wn and zeta positive and make relative steps uniform, which is what
// conditions a fit whose frequencies and damping ratios span decades.
struct ModalModel {
  Eigen::VectorXd wn0;          // rad/s, one per mode
  Eigen::VectorXd zeta0;        // one per mode
  Eigen::VectorXd a0;           // modal constant scale (1/kg), one per mode, != 0
  double residual_scale = 0.0;  // s in m/N; 0 = no residual terms
  double w_ref = 1.0;           // rad/s, usually the band's lower edge

  int modes() const { return static_cast<int>(wn0.size()); }
  int parameters() const { return 3 * modes() + (residual_scale > 0.0 ? 2 : 0); }

  // H(w) for parameters theta; if J_h_theta is not null it receives dH/dtheta
  // (parameters() values).
  std::complex<double> evaluate(const double* theta, double w,
                                std::complex<double>* J_h_theta = nullptr) const;

  // Physical values of mode i for parameters theta.
  double wn(const double* theta, int i) const;
  double zeta(const double* theta, int i) const;
  double a(const double* theta, int i) const;
};

}  // namespace frf
}  // namespace chatterlab
