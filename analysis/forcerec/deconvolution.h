// Regularized deconvolution of a dynamometer record (004 sec. 2.3, eq. 2.27; format section 4,
// method `rd`): zeroth-order Tikhonov on the whole record, with alpha by the discrepancy
// principle, GCV or the L-curve (all three reported) or a given number.
//
// Problem (004 eqs 2.23-2.27 with E12). With y(0..N-1) the record and h(k) = C Ad^(k-1) Bd the
// Markov parameters of the sampled model (model.h), the rows are y(1)..y(N-1) and the unknowns
// the held forces of intervals 0..N-2 (M = N - 1 of each):
//   G = lower-triangular Toeplitz, first column h(1..M)   (h(1) = C Bd on the diagonal)
//   f = argmin ||G f - y(1..M)||^2 + alpha ||f||^2   =  (G^T G + alpha I)^-1 G^T y(1..M)
// and the output is f(0..M-1) with the last sample repeated (N samples; sample k estimates the
// force averaged over [k/fs, (k+1)/fs)).
//
// Solver (no window, all N samples). P = the largest even 7-smooth FFT length <= M. On the first P
// unknowns G equals the circulant C_P whose first column is the periodized response
// h_P(k) = C Ad^(k-1) (I - Ad^P)^-1 Bd minus a rank-n term (n = model order):
//   G_P = C_P - O Z R,   O rows C Ad^i,  R f = x(P) (the state at the end from rest),
//   Z = Ad (I - Ad^P)^-1            (exact, no truncation involved);
// the last s = M - P rows and unknowns are eliminated exactly by a backward Riccati (LQ tracking)
// recursion that leaves a quadratic in x(P). The normal matrix is then
//   (C_P^T C_P + alpha I) + U S U^T,   U = [R^T, C_P^T O]  (P x 2n),
// the first term diagonal in Fourier space, U supported on 2L samples around the wrap point
// (L: decay length below). Woodbury gives the solution with three length-P FFTs per alpha
// (the circulant solution, the kernel of (C_P^T C_P + alpha I)^-1 and the correction) plus FFTs
// of length ~4L for the 2n x 2n capacitance matrix. The sequences C Ad^i and Ad^i Bd are cut at
// the decay length L: the first i with ||Ad^i||_F <= decay_tolerance * max_{j<i} ||Ad^j||_F (so
// every dropped term is below decay_tolerance times the largest power norm squared); L = P when
// the model has not decayed by then (nothing is cut).
// The result is then checked against G and G^T applied by the state recursions (independent of
// the FFT algebra): relative normal-equation residual
//   ||G^T (y - G f) - alpha f|| / ||G^T y|| <= tolerance,
// refined (the same solver applied to the residual) up to max_refinements times otherwise.
//
// Tuning. A first screen evaluates, for every grid alpha, the circulant approximation on the P
// first rows in closed form (bins k, eigenvalues lambda_k of C_P, Y_k the DFT of the rows):
//   ||r||^2 ~ (M/P) (1/P) sum |alpha Y_k / (|lambda_k|^2 + alpha)|^2,
//   ||f||^2 ~ (M/P) (1/P) sum |conj(lambda_k) Y_k / (|lambda_k|^2 + alpha)|^2,
//   tr A_alpha ~ (M/P) sum |lambda_k|^2 / (|lambda_k|^2 + alpha)   (influence matrix trace,
//                exact for the circulant: its eigenvalues are the filter factors).
// `gcv` minimizes ||r||^2 / (M - tr A_alpha)^2 and `lcurve` maximizes the curvature of
// (log ||r||, log ||f||) over log alpha, both on the screen (004 sec. 3.5). `discrepancy` takes
// the screen's largest grid alpha with ||r||^2 <= M R, then walks the grid with exact
// evaluations until the exact residual holds at the chosen alpha and fails at the next larger
// one. The force is the exact solution at the chosen alpha.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/forcerec/model.h"

namespace chatterlab {
namespace forcerec {

enum class AlphaRule { kDiscrepancy, kGcv, kLcurve, kFixed };

// "discrepancy", "gcv", "lcurve", "fixed".
const char* to_string(AlphaRule rule);

struct DeconvolutionOptions {
  // Which alpha gives the force; the three rules are reported whatever this is.
  AlphaRule rule = AlphaRule::kDiscrepancy;
  // alpha (N^2/N^2, dimensionless) when rule == kFixed; finite and > 0.
  double fixed_alpha = 0.0;
  // The grid 10^(log10 alpha_min + i / per_decade), i = 0.. up to alpha_max (format: 1e-8..1e2,
  // 10 per decade, 101 values).
  double alpha_min = 1e-8;
  double alpha_max = 1e2;
  int alphas_per_decade = 10;
  // Relative size of the dropped powers of Ad (see the decay length above); 1e-13 keeps the
  // cut below the rounding of a 1e5-sample sum of O(1) terms.
  double decay_tolerance = 1e-13;
  // Stopping rule: relative normal-equation residual checked by the state recursions.
  double tolerance = 1e-10;
  // Refinement steps allowed when the first solve misses the tolerance.
  int max_refinements = 3;
};

struct LCurvePoint {
  double alpha = 0.0;
  double residual_norm_N = 0.0;  // ||G f - y||
  double solution_norm_N = 0.0;  // ||f|| over the M unknowns
};

struct DeconvolutionResult {
  Eigen::VectorXd force_N;  // N samples (empty when the step failed before solving)
  double alpha = std::numeric_limits<double>::quiet_NaN();  // the one used for force_N
  AlphaRule rule = AlphaRule::kDiscrepancy;                 // what chose it (after fallback)
  double alpha_discrepancy = std::numeric_limits<double>::quiet_NaN();  // NaN: rule unsatisfied
  double alpha_gcv = std::numeric_limits<double>::quiet_NaN();
  double alpha_lcurve = std::numeric_limits<double>::quiet_NaN();
  bool discrepancy_satisfied = false;
  double discrepancy_target_N2 = 0.0;  // (N - 1) R
  std::vector<LCurvePoint> lcurve;     // every grid alpha, circulant screen (for the figure)
  std::vector<LCurvePoint> exact;      // alphas solved exactly, in the order solved
  double residual_norm_N = std::numeric_limits<double>::quiet_NaN();    // exact, at alpha
  double solution_norm_N = std::numeric_limits<double>::quiet_NaN();    // exact, at alpha
  double relative_residual = std::numeric_limits<double>::quiet_NaN();  // the stopping rule
  int refinements = 0;
  Eigen::Index fft_size = 0;      // P
  Eigen::Index tail_length = 0;   // s = M - P
  Eigen::Index decay_length = 0;  // L
  StepSummary summary;
};

// @param model         sampled dynamometer model (stable: spectral radius of Ad < 1)
// @param y_N           the record, N >= 8 samples
// @param noise_var_N2  R, the noise variance of y (air window or noise_var_N2); finite, > 0
// @throws std::invalid_argument for shapes (model sizes, N < 8), InputError for option values,
//         R and an unstable model. Non-finite samples and a missed tolerance are reported in
//         the summary (failed); an unsatisfiable discrepancy rule falls back to the GCV alpha
//         with a warning (R too small for the data, or a wrong model).
DeconvolutionResult deconvolve_tikhonov(const DiscreteModel& model,
                                        const Eigen::Ref<const Eigen::VectorXd>& y_N,
                                        double noise_var_N2,
                                        const DeconvolutionOptions& options = {});

// One exact solve at a given alpha (finite, > 0): no screen, no rules (alpha_* NaN, lcurve
// empty, exact holds the one solve); options.rule and fixed_alpha are ignored. For a study at a
// known alpha (another model, a timing per solve). Same checks and summary as above.
DeconvolutionResult deconvolve_tikhonov_at(const DiscreteModel& model,
                                           const Eigen::Ref<const Eigen::VectorXd>& y_N,
                                           double alpha, const DeconvolutionOptions& options = {});

}  // namespace forcerec
}  // namespace chatterlab
