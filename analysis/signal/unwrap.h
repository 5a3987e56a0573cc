// Phase unwrapping: an angle sampled modulo 2 pi made continuous.
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace signal {

// phase[i] + 2 pi k_i, with k_0 = 0 and k_i = k_(i-1) + 1 when the input falls by more than pi
// from sample i - 1 to i (phase[i] - phase[i-1] < -pi), k_(i-1) - 1 when it rises by more than
// pi, k_(i-1) otherwise. A phase that advances by less than half a turn per sample comes out
// increasing (theta_1 from the tachometer: 2 pi / (samples per revolution) per sample).
// @param phase_rad  any length (empty and single samples come back unchanged)
Eigen::VectorXd unwrap_phase_rad(const Eigen::Ref<const Eigen::VectorXd>& phase_rad);

}  // namespace signal
}  // namespace chatterlab
