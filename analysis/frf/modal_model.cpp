#include "analysis/frf/modal_model.h"

#include <cmath>

namespace chatterlab {
namespace frf {

double ModalModel::wn(const double* theta, int i) const { return wn0[i] * std::exp(theta[3 * i]); }
double ModalModel::zeta(const double* theta, int i) const {
  return zeta0[i] * std::exp(theta[3 * i + 1]);
}
double ModalModel::a(const double* theta, int i) const { return a0[i] * theta[3 * i + 2]; }

std::complex<double> ModalModel::evaluate(const double* theta, double w,
                                          std::complex<double>* J_h_theta) const {
  std::complex<double> h(0.0, 0.0);
  for (int i = 0; i < modes(); ++i) {
    const double wn_i = wn(theta, i);
    const double zeta_i = zeta(theta, i);
    const double a_i = a(theta, i);
    // 003 eq. 4-27 with A_i = 1/m_i.
    const std::complex<double> d(wn_i * wn_i - w * w, 2.0 * zeta_i * wn_i * w);
    const std::complex<double> term = a_i / d;
    h += term;
    if (J_h_theta != nullptr) {
      const std::complex<double> term_over_d = term / d;
      // dH/dln(wn) = wn dH/dwn = -A/d^2 (2 wn^2 + 2 j zeta wn w)
      J_h_theta[3 * i] =
          -term_over_d * std::complex<double>(2.0 * wn_i * wn_i, 2.0 * zeta_i * wn_i * w);
      // dH/dln(zeta) = zeta dH/dzeta = -A/d^2 (2 j zeta wn w)
      J_h_theta[3 * i + 1] = -term_over_d * std::complex<double>(0.0, 2.0 * zeta_i * wn_i * w);
      J_h_theta[3 * i + 2] = a0[i] / d;
    }
  }
  if (residual_scale > 0.0) {
    const int k = 3 * modes();
    const double mass_line = (w_ref / w) * (w_ref / w);
    h += residual_scale * (theta[k] - theta[k + 1] * mass_line);
    if (J_h_theta != nullptr) {
      J_h_theta[k] = residual_scale;
      J_h_theta[k + 1] = -residual_scale * mass_line;
    }
  }
  return h;
}

}  // namespace frf
}  // namespace chatterlab
