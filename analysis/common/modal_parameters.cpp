#include "analysis/common/modal_parameters.h"

#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {

double natural_frequency_hz(const ModalParameters& p) {
  return std::sqrt(p.k_N_m / p.m_kg) / kTwoPi;
}

double damping_ratio(const ModalParameters& p) {
  return p.c_kg_s / (2.0 * std::sqrt(p.k_N_m * p.m_kg));
}

}  // namespace chatterlab
