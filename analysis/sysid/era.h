// A discrete state-space model realized from a measured frequency response by the Eigensystem
// Realization Algorithm (001 sec. 3.2), with the model order from the Gavish-Donoho optimal
// hard threshold and the unstable part removed by an ordered Schur split. Every free choice is
// the one fixed by the format (docs/format/test-kinds.md, kind frf, steps 1-8), so that two
// implementations of the format agree:
//
// 1. the FRF on a uniform grid f_m = m rate / (2M), m = 0..M, M = round(rate / (2 df)):
//    linear interpolation of re and im; held below the first point; above the last point
//    G(f_last) (1 + cos(pi (f - f_last) / (rate/2 - f_last))) / 2; real at rate/2;
// 2. Markov parameters y_k = Re IDFT (1/N, N = 2M) of the Hermitian spectrum ("via inverse
//    Fourier transform", 001 sec. 3.2; no 1/Ts factor: the model runs at Ts = 1/rate);
// 3. Hankel matrices H[i][j] = y[i+j+1], H'[i][j] = y[i+j+2], i, j < alpha =
//    min(floor(N/4), 1000) (001 eqs 3.13, 3.21 with their last index corrected);
// 4. singular values of H (3.15), order r = #{s_i > max(2.8584 median s, alpha eps s_1)}
//    (Gavish-Donoho, square matrix, unknown noise; the floor keeps noise-free data exact), or
//    lambda*(1) sqrt(alpha) sigma for a known noise level sigma of y; then r = min(r, cap,
//    alpha - 1);
// 5. A = S^-1/2 U^T H' V S^-1/2, B = first column of S^1/2 V^T, C = first row of U S^1/2
//    (3.20, 3.22, 3.23 corrected), D = y_0 (3.12; 001 never states it);
// 6. stable part (3.24-3.27): real Schur form ordered with |z| < 1 - 1e-9 first, S solving the
//    Sylvester equation A11 S - S A22 + A12 = 0 (001 calls it a Lyapunov equation), keep A11,
//    B1 - S B2, C1, D; unstable states are dropped, not reflected;
// 7. fit % = 100 (1 - |G - G_model| / |G - mean G|) over the measured points 0 < f <= rate/2;
// 8. modes from the poles with Im z > 0.
//
// Speed: a square Hankel matrix of a single-input single-output sequence is symmetric, so its
// singular values are the magnitudes of its eigenvalues and its singular vectors are
// eigenvectors (v_i = sign(lambda_i) u_i). All eigenvalues come from a Householder
// tridiagonalization (Eigen), and only the r kept eigenvectors by inverse iteration (LAPACK
// dstebz/dstein) and the Householder back-transform: 0.15 s for alpha = 1000, against about
// 1 s for a full SVD with vectors (docs/sysid.md).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/sysid/state_space.h"

namespace chatterlab {
namespace sysid {

// The median-rule coefficient for a square matrix, as the format fixes it (omega(1) =
// 2.85843 by gavish_donoho.h, rounded).
inline constexpr double kEraMedianRuleOmega = 2.8584;
// Poles with |z| < kStableRadius are stable (step 6).
inline constexpr double kStableRadius = 1.0 - 1e-9;

struct EraOptions {
  // Largest model order kept (era_max_order of the format). >= 1.
  int max_order = 40;
  // Largest Hankel size alpha. >= 2.
  int max_hankel_size = 1000;
  // Standard deviation of the noise of the Markov parameters y_k, when known (simulations):
  // the known-noise threshold lambda*(1) sqrt(alpha) sigma replaces the median rule. NaN:
  // unknown.
  double markov_noise_std = std::numeric_limits<double>::quiet_NaN();
  // The grid step of step 1 for data that is not uniform (markov_parameters_from_frf); NaN:
  // the data's own uniform step.
  double grid_step_hz = std::numeric_limits<double>::quiet_NaN();
};

// Steps 1-2. @param f_hz rising on a uniform step df (each step within 0.1 % of the median
// step), f_0 >= 0, f_last <= rate/2, at least 2 points; @param G the FRF at f_hz.
// @param grid_step_hz NaN: df is the mean step of uniform data (checked). Given: the points
// need only rise (a sweep FRF's band with its 0 Hz point, kind sweep-frf), and M = round(rate
// / (2 grid_step_hz)).
// @throws InputError naming freq_hz (and the rule) or the rate.
Eigen::VectorXd markov_parameters_from_frf(
    const Eigen::Ref<const Eigen::VectorXd>& f_hz, const Eigen::Ref<const Eigen::VectorXcd>& G,
    double sample_rate_hz, double grid_step_hz = std::numeric_limits<double>::quiet_NaN());

// Steps 3-5: the full-order realization, stable or not.
struct EraRealization {
  StepSummary summary;              // failed when the threshold keeps no singular value
  DiscreteStateSpace model;         // order r
  Eigen::VectorXd singular_values;  // all alpha of them, descending
  double threshold = std::numeric_limits<double>::quiet_NaN();
  int order_by_threshold = 0;  // before the caps
  int hankel_size = 0;         // alpha (rows = columns)
  double svd_s = 0.0;          // wall time of the singular value step
};

// @param y Markov parameters y_0..y_{N-1}, N >= 8 (alpha = min(floor(N/4), cap) >= 2).
// @throws InputError for non-finite y, N < 8 or bad options.
EraRealization era_realize(const Eigen::Ref<const Eigen::VectorXd>& y, double sample_rate_hz,
                           const EraOptions& options = {});

// Step 6.
struct StableSplit {
  StepSummary summary;        // failed if LAPACK's Schur or Sylvester step fails
  DiscreteStateSpace stable;  // the kept part (order may be 0)
  int removed = 0;            // unstable states dropped
  // max |W^-1 A_sep W - blkdiag(A11, A22)| / |A|: the decoupling's check (zero to rounding).
  double decoupling_residual = std::numeric_limits<double>::quiet_NaN();
};
StableSplit stable_part(const DiscreteStateSpace& model);

// Step 7: 100 (1 - |G - G_model| / |G - mean G|), complex 2-norms. @throws InputError for
// sizes that differ or fewer than 2 points.
double frf_fit_pct(const Eigen::Ref<const Eigen::VectorXcd>& G,
                   const Eigen::Ref<const Eigen::VectorXcd>& G_model);

// Steps 1-8 on a measured FRF.
struct EraResult {
  StepSummary summary;
  EraRealization realization;  // the full-order model and its singular values
  DiscreteStateSpace model;    // the stable part: what the observer uses
  int unstable_removed = 0;
  double decoupling_residual = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXcd poles;  // of model
  std::vector<DiscreteMode> modes;
  double dc_gain = std::numeric_limits<double>::quiet_NaN();
  double fit_pct = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd fit_f_hz;      // the measured points 0 < f <= rate/2
  Eigen::VectorXcd fit_G;        // their measured values
  Eigen::VectorXcd fit_G_model;  // and the model's
  int markov_length = 0;         // N
  double runtime_s = 0.0;
};

// Never throws for bad data: the summary says what failed (with the InputError's message).
EraResult era_identify(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                       const Eigen::Ref<const Eigen::VectorXcd>& G, double sample_rate_hz,
                       const EraOptions& options = {});

}  // namespace sysid
}  // namespace chatterlab
