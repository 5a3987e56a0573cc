// Sliding-mode observer (SMO) force reconstruction behind a table dynamometer: 004 eqs 2.12-2.22
// in discrete time, as EXPERIMENT_FORMAT.md sec. 4 (`smo`) fixes it.
//
// Canonical form (004 eqs 2.15-2.17, E9). With Tc = [N^T; C] (N an orthonormal basis of null(C))
// and Tb = [[I, -Bc(1:n-1) / Bc(n)], [0, 1]] (Bc = Tc B), T = Tb Tc gives
//   [x1; y]' = [[A11, A12], [A21, A22]] [x1; y] + [0; B2] F,   y = [0 ... 0 1] [x1; y],
// B2 = C B = b1 (1/s; relative degree one: B2 != 0). eig(A11) are the zeros of the model; the
// observer needs them in the open left half plane (minimum phase).
//
// Observer (004 eq. 2.18, E10: Gn without the B factor, F_hat = nu / B2). With e = y_hat - y (N)
// and e1 = x1_hat - x1, the errors obey 004 eqs 2.20-2.21:
//   e1' = A11 e1,   e' = A21 e1 + a22s e + nu - B2 F,   nu = -rho e / (delta + |e|)   (2.22).
// (2.22 is the smoothed switching function, not a saturation: inside |e| << delta it is the
// linear -rho e / delta, outside it tends to -rho sign(e); 2.13 is its delta -> 0 limit.)
//
// Discretization (the format's). Between samples the observer is fed the one continuous signal
// through the samples that the sampled model can produce: its output under a zero-order hold on
// the force F_zoh(k), the force of interval k that reproduces y(k+1) from rest (the one-step
// inverse of the sampled model; linear or cubic interpolation of y would misread resonant
// content). Then x1 follows the model from x1(0) = 0 and so does x1_hat (e1(0) = 0, so e1 = 0 by
// 2.20), and 2.21 is the scalar, piecewise-autonomous ODE
//   e' = a22s e - rho e / (delta + |e|) - B2 F_zoh(k)   on [k dt, (k+1) dt),   e(0) = 0,
// carried across intervals. Sample k of the estimate is the mean of nu / B2 over interval k.
// The ODE is solved exactly per interval (smo_output_error_step): on each side of e = 0 it is
// separable with a rational right-hand side, so the time to a crossing and the integral of e are
// closed forms (two logarithms), and e at the interval end is either the equilibrium itself (the
// common case: the layer's time constant delta / rho = 0.65 us against dt = 98 us) or the root
// of a monotone scalar equation (a few safeguarded Newton steps). An explicit integrator would
// need steps well below delta / rho: some 150 per sample at the defaults.
//
// Boundary-layer bandwidth. Linearised about its operating point |e*| (|nu| ~ |B2 F|, so
// |e*| / (delta + |e*|) = m, m = max|B2 F_zoh| / rho), 2.22 has slope kappa = (rho / delta)
// (1 - m)^2 and the output error is the first-order low-pass lambda = kappa - a22s (time constant
// ~ delta / rho). Sampled as above (held input, interval-mean output) the estimate is exactly
//   F_hat(z) = g [1 - beta (z - 1) / (z - phi)] F_zoh(z),
//   g = kappa / lambda,  phi = e^(-lambda dt),  beta = (1 - phi) / (lambda dt),
// whose delay is 1 / lambda (s) and whose amplitude loss at high frequency is about
// beta (1 - cos w dt): a fractional delay by linear interpolation. Warning (the format's "rho /
// delta too small"): the amplitude error | |F_hat / F_zoh| - 1 | at K f_tp above
// SmoOptions::max_amplitude_error, or m >= 1 (rho cannot hold the sliding motion).
#pragma once

#include <Eigen/Core>
#include <complex>
#include <limits>

#include "analysis/common/summary.h"
#include "analysis/forcerec/model.h"

namespace chatterlab {
namespace forcerec {

struct SmoOptions {
  // rho of 004 eq. 2.22 (N/s), finite and > 0. Default: ten times 004's simulation value 1e7, so
  // that the boundary layer (time constant delta / rho = 0.65 us) leaves the tooth harmonics
  // alone. 004's experimental rule rho = max|y| |B2| low-passes and delays (see the warning).
  double rho_N_s = 1.0e8;
  // delta of 004 eq. 2.22 (N), the boundary layer, finite and > 0 (004's simulation value).
  double delta_N = 65.0;
  // A22s of 004 eqs 2.18-2.21 (1/s), the chosen output-error dynamics, finite and < 0 (004).
  double a22s_1_s = -1.0;
  // Bandwidth warning: evaluated at harmonic_count * tooth_freq_hz when both are > 0 (format:
  // f_tp = spindle_rpm teeth / 60, K = min(12, floor(0.4 fs / f_tp))); >= 0.
  double tooth_freq_hz = 0.0;
  int harmonic_count = 0;
  // Warning when the sampled, linearised boundary layer changes the amplitude at K f_tp by more
  // than this (>= 0). 0.02: the defaults lose 1.2 % at 0.4 fs (fs = 10240 Hz, 8 x 511.5 Hz), a
  // fractional delay of 0.0066 samples; 004's experimental rule loses tens of percent.
  double max_amplitude_error = 0.02;
};

// 004 eqs 2.15-2.17: the model in the SMO's canonical coordinates [x1; y] = T x.
struct CanonicalForm {
  Eigen::MatrixXd A;     // n x n: T A T^-1 = [[A11, A12], [A21, A22]]
  Eigen::VectorXd B;     // n: T B = [0 ... 0 B2]
  Eigen::RowVectorXd C;  // n: C T^-1 = [0 ... 0 1]
  Eigen::MatrixXd T;     // n x n: Tb Tc
  double B2 = 0.0;       // C B = b1 (1/s)

  Eigen::MatrixXd A11() const { return A.topLeftCorner(A.rows() - 1, A.cols() - 1); }
};

// @throws std::invalid_argument for a model of inconsistent shape, order < 2, C = 0, or C B = 0
// (relative degree above one: |C B| <= 1e-12 |C| |B|).
CanonicalForm canonical_form(const ContinuousModel& model);

// The one-step inverse of the sampled model, F_zoh(k) = the force of interval k that, held, makes
// the model from rest (x(0) = 0, so y(0) is read as 0) reproduce y(k+1). With z = Tc x (last
// coordinate y) and the first n-1 coordinates rotated to the real Schur form of the inverse's
// dynamics, w = U^T z1:
//   F_zoh(k) = r w(k) + d_prev y(k) + d_next y(k+1),
//   w(k+1)   = S w(k) + p y(k) + q y(k+1),         w(0) = 0,
// S quasi-upper-triangular (orthogonal change of basis: no conditioning is lost). eig(S) are the
// sampled model's zeros; the recursion is stable only when they lie inside the unit circle.
struct OneStepInverse {
  Eigen::MatrixXd S;     // (n-1) x (n-1)
  Eigen::VectorXd p, q;  // n-1
  Eigen::RowVectorXd r;  // n-1
  double d_prev = 0.0, d_next = 0.0;
  Eigen::VectorXcd sampled_zeros;  // eig(S)
  double max_zero_modulus = std::numeric_limits<double>::quiet_NaN();
};

// @throws std::invalid_argument for a model of inconsistent shape, order < 2, or C Bd = 0.
OneStepInverse one_step_inverse(const DiscreteModel& model);

// F_zoh(0..N-2) into force(0..N-2), force(N-1) = force(N-2) (y(N) is not there); force has
// y.size() entries (it may be y itself). @throws std::invalid_argument for N < 2 or a size
// mismatch.
void run_one_step_inverse(const OneStepInverse& inv, const Eigen::Ref<const Eigen::VectorXd>& y,
                          Eigen::Ref<Eigen::VectorXd> force);

// One interval of 2.21 with a held drive: e' = a22s e - rho e / (delta + |e|) - drive over dt,
// solved exactly (see the file comment). drive = B2 F_zoh(k) (N/s).
struct OutputErrorStep {
  double e_end_N = 0.0;      // e at the end of the interval
  double nu_mean_N_s = 0.0;  // mean of nu over the interval
};
OutputErrorStep smo_output_error_step(double e0_N, double drive_N_s, double dt_s,
                                      const SmoOptions& options);

// The sampled, linearised boundary-layer response F_hat / F_zoh at f_hz (file comment), for a
// reach ratio m = max|B2 F_zoh| / rho in [0, 1).
std::complex<double> smo_boundary_layer_response(const SmoOptions& options, double sample_rate_hz,
                                                 double f_hz, double reach_ratio = 0.0);

struct SmoResult {
  StepSummary summary;  // failed: non-minimum-phase model or sampled zeros, non-finite y
  double B2_1_s = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXcd zeros_rad_s;    // eig(A11): the model's zeros
  Eigen::VectorXcd sampled_zeros;  // the one-step inverse's poles
  double max_sampled_zero_modulus = std::numeric_limits<double>::quiet_NaN();
  // Bandwidth check (file comment), at the worst-case operating point m = reach_ratio. NaN
  // amplitude error when f_tp or K is not given.
  double corner_hz = std::numeric_limits<double>::quiet_NaN();            // rho / (2 pi delta)
  double effective_corner_hz = std::numeric_limits<double>::quiet_NaN();  // lambda / (2 pi)
  double reach_ratio = std::numeric_limits<double>::quiet_NaN();          // max|B2 F_zoh| / rho
  double delay_samples = std::numeric_limits<double>::quiet_NaN();        // fs / lambda
  double amplitude_error = std::numeric_limits<double>::quiet_NaN();      // at K f_tp
  bool bandwidth_warning = false;  // also a line in summary.warnings
  // N samples each (empty unless ok): sample k estimates F over [k/fs, (k+1)/fs); the output
  // error e = y_hat - y at the end of interval k (004 Figs 4.4 e-f).
  Eigen::VectorXd force;
  Eigen::VectorXd output_error_N;
};

// The format's `smo` on one axis. @param y dynamometer output (N), N >= 2. Non-finite y and a
// non-minimum-phase model (eig(A11) or the sampled zeros) go into the summary. @throws
// std::invalid_argument for a model of inconsistent shape or order < 2, C B = 0, N < 2, a
// sample_rate_hz not finite and > 0;
// InputError for bad options ("smo.rho_N_s = 0: must be finite and > 0").
SmoResult reconstruct_force_smo(const ContinuousModel& model, double sample_rate_hz,
                                const Eigen::Ref<const Eigen::VectorXd>& y,
                                const SmoOptions& options = {});

}  // namespace forcerec
}  // namespace chatterlab
