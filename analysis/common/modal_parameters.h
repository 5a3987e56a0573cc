// The modal parameters of one mode or one axis of the tool: the single-degree-of-freedom model
// m x'' + c x' + k x = F of 000 eqs 2.5-2.6. One type for the whole project: tap-test fits
// (frf::Mode adds fn, zeta), the simulator's axes (milling::AxisModal) and the estimators'
// known and identified values (estimate::ModalParameters).
#pragma once

#include <limits>

namespace chatterlab {

// No defaults: a value never measured or configured stays NaN.
struct ModalParameters {
  double m_kg = std::numeric_limits<double>::quiet_NaN();    // modal mass, > 0
  double c_kg_s = std::numeric_limits<double>::quiet_NaN();  // modal damping, >= 0
  double k_N_m = std::numeric_limits<double>::quiet_NaN();   // modal stiffness, > 0
};

// fn = sqrt(k / m) / (2 pi), Hz (000 eq. 2.6).
double natural_frequency_hz(const ModalParameters& p);
// zeta = c / (2 sqrt(k m)) (000 eq. 2.6).
double damping_ratio(const ModalParameters& p);

}  // namespace chatterlab
