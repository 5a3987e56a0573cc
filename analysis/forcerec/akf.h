// Augmented Kalman filter (AKF) force reconstruction behind a table dynamometer: 004 eqs
// 2.6-2.11 with Ad, Bd (004 E3), D = 0 (E2), as EXPERIMENT_FORMAT.md sec. 4 (`akf`) fixes it.
//
// Model: the sampled dynamometer (model.h) with the force as a random-walk state,
//   z = [x; F],  z(k+1) = A_a z(k) + [0; w(k)],  y(k) = G_a z(k) + v(k),
//   A_a = [[Ad, Bd], [0, 1]],  G_a = [C, 0],  Q = diag(Q0 = 0, S),  R = E v^2,  z(0|-1) = 0.
//
// Steady state. The format's filter starts from x0 = 0 and a large P0, and says the steady-state
// gain is fine after 0.05 s. We run the steady-state filter (the stabilizing DARE solution of
// kalman::steady_state_gain) from k = 0 with z(0|-1) = 0. Both filters are linear in y with the
// same start; they differ by the gain sequence K_k - K, which decays like rho^(2k) (rho: the
// spectral radius of A_a - L G_a, recorded below), and their estimates by a start-up transient
// that decays like rho^k. rho is at least the modulus of the slowest sampled zero: 0.965-0.975 on
// 004's x axis at 10240 Hz (rho^512 = 1e-8..2e-6: after 0.05 s the two differ by 1e-7 N at
// S >= 0.01, 1.5e-5 N at S = 1e-4; akf_test checks it against kalman::KalmanFilter with P0 = 1e6
// I), but about 0.985 on the z axis (zero at 1096 Hz, zeta 0.022: rho^512 ~ 5e-4, about 1e-2 N
// after 0.05 s on a 30 N force). Samples before 0.05 s are outside the format's evaluation
// window and E(S)'s sum.
//
// Only S/R matters (Q0 = 0). If P solves the DARE for (Q, R), then c P solves it for (c Q, c R):
//   c P = A_a (c P) A_a^T - A_a (c P) G_a^T (G_a (c P) G_a^T + c R)^-1 G_a (c P) A_a^T + c Q
// is the first equation times c. The stabilizing solution is unique, so P(cQ, cR) = c P(Q, R),
// and K = P G_a^T (G_a P G_a^T + R)^-1 is homogeneous of degree 0 in (P, R): K is unchanged.
// With Q0 = 0, Q = S e_F e_F^T, so the gain, and the estimate (linear in y with that gain from
// z = 0), are functions of S/R alone. (The time-varying filter also needs P0 scaled by c: P_k
// scales by c by induction.) akf_test checks the invariance to rounding.
//
// Lag and its removal. The force of interval k first shows in y(k+1) (h(0) = 0, 004 E12), so the
// filtered p(k|k) is the random-walk prediction of F(k) from F(k-1)'s evidence: one sample late.
// The format outputs p(k+1|k+1) as sample k. That is exactly the one-step (fixed-lag) smoothed
// estimate of F(k): F(k+1) = F(k) + w(k), and w(k) enters y only from y(k+2) on, so
//   E[F(k+1) | y(0..k+1)] = E[F(k) | y(0..k+1)] + E[w(k) | y(0..k+1)] = E[F(k) | y(0..k+1)].
// The shift removes the lag at no cost; the last sample is repeated. What remains is the
// filter's own phase at small S/R (the random-walk prior low-passes: a small S still trails).
//
// Cost. The estimate is read from the steady-state predictor
//   z(k+1|k) = Phi z(k|k-1) + L y(k),  Phi = A_a - L G_a,  L = A_a K,
//   p(k+1|k+1) = h z(k+1|k) + K_F y(k+1),  h = e_F^T - K_F G_a,
// run in the real block-diagonal modal form of Phi (2 x 2 rotation-scaling blocks and scalars:
// about 3 multiply-adds per state and sample) when Phi's eigenvectors are well conditioned, else
// in the dense form (fixed-size Eigen types for n = 2, 4, 6, 8). No allocation per sample.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/forcerec/model.h"

namespace chatterlab {
namespace forcerec {

struct AkfOptions {
  // S grid (N^2): S_min_N2 * 10^(i / S_per_decade), i = 0 .. up to S_max_N2 (format: 1e-5..1e5,
  // 10 per decade, 101 values). S_min_N2 > 0, S_max_N2 >= S_min_N2, S_per_decade >= 1.
  double S_min_N2 = 1e-5;
  double S_max_N2 = 1e5;
  int S_per_decade = 10;
  // Knee: the smallest grid S with E(S) <= (1 + knee_tolerance) min E (format: 0.02), unless E
  // dips: E(S_max) > (1 + dip_tolerance) min E (format: 0.01) takes the S of the minimum. >= 0.
  double knee_tolerance = 0.02;
  double dip_tolerance = 0.01;
  // Samples after the filter's start not summed in E(S) (format: 0.05 s, the start-up
  // transient of x0 = 0). >= 0.
  double skip_s = 0.05;
  // Tuning window of akf_tuning_window: this much of the cut window is summed (format: at least
  // 1 s; the sweep costs 101 filter passes over skip_s + tuning_length_s). > 0.
  double tuning_length_s = 1.0;
};

// The steady-state AKF for one S and R, ready to run.
struct AkfFilter {
  StepSummary summary;  // failed: S or R not finite and > 0, or the DARE failed
  double S_N2 = std::numeric_limits<double>::quiet_NaN();
  double R_N2 = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd A_a;     // (n+1) x (n+1)
  Eigen::RowVectorXd G_a;  // n+1
  Eigen::VectorXd K;       // n+1, measurement-update gain; K(n) = K_F
  Eigen::VectorXd L;       // n+1, predictor gain A_a K
  double dare_residual = std::numeric_limits<double>::quiet_NaN();
  double spectral_radius = std::numeric_limits<double>::quiet_NaN();  // of Phi = A_a - L G_a
  // The recursion (see above), in modal coordinates w = T^-1 z when `modal`, else dense (T = I).
  bool modal = false;
  int pairs = 0;         // 2 x 2 blocks first, then scalars
  Eigen::VectorXd diag;  // n+1: block diagonals p (and scalars a)
  Eigen::VectorXd off;   // pairs: q of [[p, q], [-q, p]]
  Eigen::MatrixXd Phi;   // (n+1) x (n+1): dense Phi (kept for the fallback and checks)
  Eigen::VectorXd b;     // n+1: T^-1 L
  Eigen::RowVectorXd g;  // n+1: G_a T (innovation e = y - g w)
  Eigen::RowVectorXd h;  // n+1: (e_F^T - K_F G_a) T
  double modal_residual = std::numeric_limits<double>::quiet_NaN();  // |T Lam - Phi T| / |Phi||T|
};

// Designs the steady-state AKF. Failures (S or R not finite and > 0, DARE not converging or not
// stabilizing) are in the summary. @throws std::invalid_argument for a model of inconsistent
// shape or order 0.
AkfFilter design_akf(const DiscreteModel& model, double S_N2, double R_N2);

// The reconstructed force of the format: force(k) = p(k+1|k+1), k = 0..N-2, force(N-1) =
// force(N-2), from z(0|-1) = 0. @param y dynamometer output (N), N >= 2, finite (not checked
// here: reconstruct_force_akf checks). @throws std::invalid_argument for N < 2 or a filter that
// did not succeed.
void run_akf(const AkfFilter& filter, const Eigen::Ref<const Eigen::VectorXd>& y,
             Eigen::VectorXd* force);

// E(S) of the format: sqrt(sum of (y(k) - G_a z(k|k-1))^2) over k = begin + skip .. end - 1,
// the filter started at `begin` from z = 0. @throws std::invalid_argument unless 0 <= begin,
// begin + skip < end <= y.size(), skip >= 0, and the filter succeeded.
double akf_error_norm(const AkfFilter& filter, const Eigen::Ref<const Eigen::VectorXd>& y,
                      Eigen::Index begin, Eigen::Index end, Eigen::Index skip);

// Index of the format's knee in E (ordered by increasing S): with m = min E over the finite
// entries, the argmin when the last finite entry exceeds (1 + dip_tolerance) m, else the first
// index with E <= (1 + knee_tolerance) m. -1 when no entry is finite.
Eigen::Index akf_knee_index(const Eigen::Ref<const Eigen::VectorXd>& E, double knee_tolerance,
                            double dip_tolerance);

// The S grid of the options (increasing).
Eigen::VectorXd akf_S_grid(const AkfOptions& options);

// Samples [begin, end) the filter runs over while tuning: begin = ceil(c0 fs), end = begin +
// round((skip_s + tuning_length_s) fs), cut at floor(c1 fs) and at the record's end.
// @param cut_begin_s, cut_end_s the cut window (c0 < c1; the whole record: 0, N / fs).
struct SampleWindow {
  Eigen::Index begin = 0;
  Eigen::Index end = 0;
};
SampleWindow akf_tuning_window(Eigen::Index samples, double sample_rate_hz, double cut_begin_s,
                               double cut_end_s, const AkfOptions& options = {});

struct AkfResult {
  StepSummary summary;  // failed: non-finite y, bad R or S, DARE failure at the chosen S, ...
  double S_N2 = std::numeric_limits<double>::quiet_NaN();  // the S used
  double R_N2 = std::numeric_limits<double>::quiet_NaN();
  bool S_from_knee = false;  // false: S was given
  // The error-norm curve (empty when S was given): E[i] = E(S[i]) over the tuning window, NaN
  // where the design failed (a warning says how many).
  Eigen::VectorXd S_grid_N2;
  Eigen::VectorXd E;
  Eigen::Index knee_index = -1;
  SampleWindow tuning_window;  // filter start and end; E sums from begin + skip
  Eigen::Index tuning_skip = 0;
  double spectral_radius = std::numeric_limits<double>::quiet_NaN();  // at the S used
  bool modal = false;                                                 // at the S used
  Eigen::VectorXd force;  // N samples (empty unless ok): sample k estimates F over interval k
};

// The format's `akf`: S by the knee of E(S) over `tuning_window` (akf_tuning_window), then the
// pass over the whole record. @param R_N2 the axis's noise variance. Non-finite y, R or the
// failure of every design go into the summary. @throws std::invalid_argument for y.size() < 2,
// a window outside the record, a model of inconsistent shape; InputError for bad options.
AkfResult reconstruct_force_akf(const DiscreteModel& model,
                                const Eigen::Ref<const Eigen::VectorXd>& y, double R_N2,
                                const SampleWindow& tuning_window, const AkfOptions& options = {});

// The same with a given S (format: akf_S_N2 a number): no sweep.
AkfResult reconstruct_force_akf_fixed_S(const DiscreteModel& model,
                                        const Eigen::Ref<const Eigen::VectorXd>& y, double R_N2,
                                        double S_N2);

}  // namespace forcerec
}  // namespace chatterlab
