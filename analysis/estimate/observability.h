// Local observability of the EKF models (000 sec. 4.5, eq. 4.33): the rank of
//   O = [H; H F; H F^2; ...; H F^(N-1)]
// with F = J_f_x at an operating point (state, force input) and H the deflection selector, F of
// the forward-Euler model of 000 eqs 4.10, 4.17, 4.25 (F = I + T A, A the Jacobian of the
// continuous model 000 eqs 2.5-2.6).
// 000 finds rank 3 of 5 (ekf-modal-x), 6 of 7 (ekf-modal-xy) and 6 of 6 (ekf-coeff-xy while a
// tooth cuts).
//
// Computation. With A = (F - I) / T (the continuous model's Jacobian), H F^i =
// sum_j C(i, j) T^j H A^j, so O = B O_A with O_A = [H; H A; ...; H A^(N-1)] and B block
// lower-triangular with diagonal blocks T^i I: rank O = rank O_A exactly, for any T > 0.
// Both are formed in scaled coordinates, which change no rank:
//   x = S x~ with S = diag(d, w_n d per deflection axis, |theta_i| per parameter), time in units
//   of 1 / w_n (w_n = sqrt(k / m) at the operating point), measurements in units of d,
// where d = max over axes of |p_a| and |v_a| / w_n (1e-6 m if all are zero). The rank is the
// number of singular values above relative_tolerance * the largest.
// ObservabilityForm::kContinuous (default) ranks O~_A, whose spectrum does not depend on T.
// kDiscreteEq4_33 ranks eq. 4.33 itself, O~ = [H~; H~ F~; ...] with F~ = S^-1 F S: its singular
// values in the parameter directions are (w_n T)^2 (8e-6 at T = 5e-7 s) times O_A's, so it needs
// relative_tolerance below (w_n T)^2 times the continuous form's; with 1e-12 both forms give the
// same ranks at T = 5e-7 s (tests/analysis/estimate/estimate_observability_test.cpp).
#pragma once

#include <Eigen/Core>

#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/tool_model.h"

namespace chatterlab {
namespace estimate {

enum class ObservabilityForm { kContinuous, kDiscreteEq4_33 };

struct ObservabilityOptions {
  ObservabilityForm form = ObservabilityForm::kContinuous;
  // A singular value of the scaled O_A at or below this fraction of the largest is zero.
  // Structural rank deficiency leaves singular values at rounding level (< 1e-15 relative in the
  // tests); over a revolution of 000's cut the smallest nonzero ones of the continuous form are
  // >= 1.7e-5 relative (kContinuous; see above for kDiscreteEq4_33).
  double relative_tolerance = 1e-9;
};

struct ObservabilityResult {
  int rank = 0;
  int states = 0;                   // N
  Eigen::VectorXd singular_values;  // of the scaled O_A (or O), relative to the largest,
                                    // descending
  double relative_tolerance = 0.0;
  bool observable() const { return states > 0 && rank == states; }
};

// At the operating point `state` (estimator_states(id) values, ordered as the variant's
// EkfResult::history.columns; per-tooth: one filter's x, xdot, y, ydot, Kt_p, Kr_p) with force
// input `input` and held m, c, k (`held`, for the parameters the variant does not estimate; the
// coefficient filters hold all three). Throws InputError for a state of the wrong size, a
// non-finite value, m <= 0, k <= 0 or time_step_s <= 0.
ObservabilityResult observability(EstimatorId id, const Eigen::VectorXd& state,
                                  const ForceInput& input, const ModalParameters& held,
                                  double time_step_s, const ObservabilityOptions& options = {});

}  // namespace estimate
}  // namespace chatterlab
