// Joint identification of a cut test (issue 13; docs/identification.md, "Joint estimate"): the
// offset angle, the modal parameters and every tooth's Kt_p, Kr_p fitted together by nonlinear
// least squares (Ceres, Levenberg-Marquardt) to the measured mean revolution, started from the
// sequence's result (identification.h), with 95 % intervals from the Jacobian at the optimum.
//
// Model. The steady revolution of the simulator (milling/simulation.h; 000 eqs 2.3-2.7 with the
// regenerative chip of the simulated deflections, so no measured deflection enters the chip and
// the fit has no errors in its variables), m, c, k equal on x and y (000 sec. 5.1), no edge
// terms, at the comparison window's depth. Residuals on the measured phase grid phi_j
// (revolution_mean.h), as in the offset search (sync/offset_search.h):
//   r_j = x_meas(phi_j) - x_sim(phi_j + delta),   r_(N+j) = y_meas(phi_j) - y_sim(phi_j + delta),
// the simulated revolution interpolated by periodic cubic (Catmull-Rom) interpolation.
//
// Scale. Deflections fix m, c, k and K only up to one common factor (docs/identification.md,
// "Scale"): the fitted parameters are the scale-free ones,
//   theta = (delta, ln fn, ln zeta, ln(Kt_p / k), ln(Kr_p / k) for p = 1..n),
// and k is held at the start's stiffness (the sequence's, on the hammer test's scale). m, c, Kt_p,
// Kr_p follow from theta and k; their intervals are conditional on k, which a cut cannot
// identify and which is reported as held.
//
// Intervals. With J the Jacobian of r at the optimum (central differences of the simulation) and
// J^+ its pseudo-inverse, cov(theta) = J^+ Sigma J^+^T, Sigma the residuals' covariance. The
// residuals are not white: the mean revolution is interpolated linearly between samples at the
// tachometer's fractional positions, which correlates neighbouring phase points (up to 0.5 at
// lag 1), and a real cut adds model error. Sigma is therefore the stationary (Toeplitz) estimate
// from the residual autocovariance gamma(l) = sum_j r_j r_(j+l) / (2N - P) (periodic, each axis,
// pooled), truncated at the lag L before the first lag whose autocorrelation is within the white
// noise band +-2 / sqrt(2N) (at most correlation_lags). Two linear interpolations correlate up to
// lag 2; a truncated kernel is unbiased for such short correlation, where Bartlett's weights
// (Newey-West) left the intervals about 10 % narrow in a bootstrap (docs/identification.md). With
// white residuals it is s^2 I and the interval is the classic s^2 (J^T J)^-1; it is never taken
// narrower than that. A value v(theta) gets
// v +- 1.959964 sqrt(grad v^T cov grad v) (delta method), the variance never below its value with
// white residuals. Every parameter with a share of at least 1e-3 in a near-singular direction
// (below) has an unbounded interval. A singular value
// below JointIdentificationOptions::singular_ratio times the largest is a near-singular
// direction: its parameters are named and their intervals are infinite. A value whose interval is
// wider than its own magnitude is flagged not identifiable from this cut.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/revolution_mean.h"

namespace chatterlab {
namespace estimate {

// Defaults: docs/identification.md, "Joint estimate".
struct JointIdentificationOptions {
  int simulated_revolutions = 60;  // from rest at the window's depth; the last one is fitted, >= 3
  int max_iterations = 60;         // Levenberg-Marquardt iterations, >= 1
  double singular_ratio = 1e-6;    // near-singular direction below this ratio, in (0, 1)
  // A simulated revolution that still changes by more than this fraction (RMS) between its last
  // two revolutions is not steady: the fit fails (chatter, or a transient too slow for the run).
  double settle_tolerance = 0.01;
  // Largest lag of the residual autocovariance in the interval's covariance, >= 0 (0: white
  // residuals).
  int correlation_lags = 20;
};

// One value with its 95 % interval [lo, hi] (NaN when it has none, infinite along a near-singular
// direction).
struct IntervalValue {
  double value = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();  // standard error
  double lo = std::numeric_limits<double>::quiet_NaN();
  double hi = std::numeric_limits<double>::quiet_NaN();
  // The interval is narrower than |value| and along no near-singular direction.
  bool identifiable = false;
  bool contains(double truth) const { return truth >= lo && truth <= hi; }
};

struct JointIdentificationResult {
  StepSummary summary;  // fails when the start is invalid or the solver does not converge
  bool converged = false;
  std::string termination;  // Ceres's termination message
  int iterations = 0;
  int simulations = 0;  // simulator runs, the Jacobians' included
  double runtime_s = 0.0;
  int residuals = 0;                                                    // 2N
  int parameters = 0;                                                   // 3 + 2 n
  double rms_error_m = std::numeric_limits<double>::quiet_NaN();        // RMS of r at the optimum
  double start_rms_error_m = std::numeric_limits<double>::quiet_NaN();  // ... at the start
  double relative_error = std::numeric_limits<double>::quiet_NaN();     // / RMS of the measured
  double residual_sd_m = std::numeric_limits<double>::quiet_NaN();      // s = sqrt(gamma(0))
  double residual_correlation_lag1 = std::numeric_limits<double>::quiet_NaN();  // gamma(1) / s^2
  int correlation_lags = 0;                                                     // L, the lags used
  // Long-run variance of the residuals / s^2: how much wider the intervals are than with white
  // residuals (squared).
  double variance_inflation = std::numeric_limits<double>::quiet_NaN();
  double condition = std::numeric_limits<double>::quiet_NaN();  // smallest / largest singular value
  // Near-singular directions, each as "a*ln fn + b*ln zeta ..." (the largest components).
  std::vector<std::string> singular_directions;

  // The identified values (95 % intervals). The offset in degrees in [0, 360) (its interval may
  // reach past either end).
  IntervalValue offset_deg;
  IntervalValue fn_hz, zeta;
  IntervalValue m_kg, c_kg_s;
  double k_N_m = std::numeric_limits<double>::quiet_NaN();      // held: the scale anchor
  std::vector<IntervalValue> Kt_N_m2, Kr_N_m2;                  // per tooth
  std::vector<IntervalValue> Kt_over_k_per_m, Kr_over_k_per_m;  // scale-free K_p / k, 1/m

  // The identified set as the other steps take it.
  ModalParameters modal() const { return {m_kg.value, c_kg_s.value, k_N_m}; }
  std::vector<CuttingCoefficients> coefficients() const;
  // The names of the values flagged not identifiable ("c_kg_s", "Kt2_N_m2", ...).
  std::vector<std::string> not_identifiable() const;
};

// Fits the model above to `measured` (a mean revolution on N >= 8 phase points).
// @param cut_model  tool, cut conditions and chip model of the simulated revolution; its depth,
//                   modal parameters and coefficients are replaced
// @param depth_m    axial depth of the measured revolutions, m, > 0
// @param start_offset_deg, start_modal, start_coefficients  the start (the sequence's result);
//                   start_modal.k_N_m is the scale anchor; one coefficient pair per tooth
// @throws InputError for options that break their rules or a start that is not finite and
//         positive (naming it)
JointIdentificationResult identify_joint(const sync::RevolutionMean& measured,
                                         const milling::SimulationOptions& cut_model,
                                         double depth_m, double start_offset_deg,
                                         const ModalParameters& start_modal,
                                         const std::vector<CuttingCoefficients>& start_coefficients,
                                         const JointIdentificationOptions& options = {});

}  // namespace estimate
}  // namespace chatterlab
