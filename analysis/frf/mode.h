// One single-DOF mode in physical (m, c, k) and modal (fn, zeta) form, 000 eqs 2.5-2.6.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "analysis/common/summary.h"  // InputError

namespace chatterlab {
namespace frf {

// m x'' + c x' + k x = F (000 eq. 2.5), m, c, k as common/modal_parameters.h (a Mode is used
// wherever modal parameters are, e.g. as a simulator axis), with its modal form
// fn = sqrt(k/m)/(2 pi), zeta = c / (2 sqrt(k m)) (natural_frequency_hz, damping_ratio).
struct Mode : ModalParameters {
  double fn_hz = 0.0;  // undamped natural frequency
  double zeta = 0.0;   // damping ratio
};

// @throws InputError unless m > 0, k > 0, c >= 0 (all finite)
Mode mode_from_mck(double m_kg, double c_kg_s, double k_N_m);
// k = m wn^2, c = 2 zeta sqrt(k m).
// @throws InputError unless fn > 0, m > 0, zeta >= 0 (all finite)
Mode mode_from_modal(double fn_hz, double zeta, double m_kg);

// The mode that dominates a tool's deflection among several fitted ones (the tool mode of a
// tap test): the largest peak receptance |H(wn)| = 1 / (c wn) (000 eq. 2.5 at resonance), the
// first of equal ones. Empty when `modes` is.
std::optional<Mode> dominant_mode(const std::vector<Mode>& modes);

// Receptance (m/N) of a sum of modes, 003 eq. 4-27 with A_i = 1/m_i:
//   H(w) = sum_i (1/m_i) / (wn_i^2 - w^2 + 2 j zeta_i wn_i w).
// @param f_hz  frequencies, any length
Eigen::VectorXcd receptance(const std::vector<Mode>& modes,
                            const Eigen::Ref<const Eigen::VectorXd>& f_hz);

}  // namespace frf
}  // namespace chatterlab
