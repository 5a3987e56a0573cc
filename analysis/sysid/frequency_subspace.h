// A second identification method beside ERA (era.h), for the comparison that 001 sec. 3.3
// lacks (notes/001.md sec. 4: only MATLAB's modalfit, and no numbers): the frequency-domain
// subspace algorithm of T. McKelvey, H. Akcay and L. Ljung, "Subspace-based multivariable
// system identification from frequency response data", IEEE TAC 41(7), 1996, pp. 960-979. Of
// its two algorithms this is the second (the projection algorithm, any frequency spacing),
// discrete time, single input and output, without the noise weighting (see step 3):
//
// 1. z_k = exp(j w_k), w_k = 2 pi f_k / rate, for the given points 0 <= f_k <= rate/2. For
//    each point the state-space model G(z) = D + C (zI - A)^-1 B satisfies, with
//    X(z) = (zI - A)^-1 B and W_q(z) = [1, z, .., z^(q-1)]^T,
//      W_q(z) G(z) = O_q X(z) + Gamma_q W_q(z),
//    O_q = [C; CA; ..; CA^(q-1)] the extended observability matrix, Gamma_q the lower
//    triangular Toeplitz matrix of D, CB, CAB, ..;
// 2. stacked over the points and split into real and imaginary parts (A, B, C, D are real):
//      G_re = O_q X_re + Gamma_q W_re,   G_re, W_re: q x L real,
//    with L = 2 K real columns for K points, less one for each point at f = 0 or rate/2
//    (whose imaginary column is zero);
// 3. the input term is eliminated by projecting on the orthogonal complement of the row space
//    of W_re: the QR factorization of [W_re; G_re]^T gives the lower triangular
//    [W_re; G_re] = [R11 0; R21 R22] [Q1^T; Q2^T], and G_re Pi^perp = R22 Q2^T, so the column
//    space of R22 (q x q) is that of O_q. The paper weights R22 with the noise covariance for
//    consistency. For white FRF noise (the FFT of white noise) on the uniform grid
//    f_m = m rate / N, m = 0..N/2, the noise of G_re has the row covariance sigma^2
//    Re(sum_k W_q(z_k) W_q(z_k)^*), whose entry (i, l) is sum_k cos((i - l) w_k): K on the
//    diagonal and (1 + (-1)^(i-l)) / 2 (0 or 1) off it. That is K I to O(q / K), so the
//    weighting is left out;
// 4. SVD R22 = U S V^T; the order n is options.order, or by the Gavish-Donoho median rule on
//    the q singular values S: n = #{s_i > max(omega(b) median s, sqrt(q L) eps |G_re|_F)},
//    with the aspect ratio b = q / (L - q) of the projected matrix (q rows; its row space has
//    dimension L - q) and omega(b) of gavish_donoho.h (b = 0.041 for q = 80 and N = 2048);
//    then n = min(n, max_order, q - 1). The floor keeps noise-free data exact, as ERA's does
//    (era.h step 4); it is relative to the data (G scaled to unit rms), not to s_1, because
//    the rounding of the projection is: measured on exact FRFs of 10..30 states, the
//    singular values past the order are 1.1e-15 .. 1.8e-15 |G_re|_F, the floor 9e-14
//    |G_re|_F, and the smallest kept one 4e-11 |G_re|_F (30 states);
// 5. O = U_n (the first n left singular vectors): C = its first row, A = the least-squares
//    solution of O(1:q-1, :) A = O(2:q, :) (shift invariance);
// 6. unstable poles (|z| >= 1 - 1e-9, era.h kStableRadius): the ordered Schur split of era.h
//    (stable_part) keeps the stable pair (A11, C1); B and D are fitted after it, so that the
//    kept model is the least-squares one for its poles (ERA instead keeps B1 - S B2);
// 7. B and D by linear least squares on the complex FRF, real and imaginary parts stacked:
//      min over real B, D of sum_k |G_k - D - C (z_k I - A)^-1 B|^2,
//    with C (z_k I - A)^-1 from the complex Schur form of A (one triangular solve per point);
// 8. fit % = frf_fit_pct (era.h step 7) over the points 0 < f <= rate/2, as ERA's.
//
// Block rows q: the paper needs q > n; the median rule needs q > 2n, so that the median
// singular value is a noise one. Default q = 2 max_order (80). Measured in the validation
// study (era_validation.h: 50 systems of 10..30 states, N = 2048, median fit % at 10 / 0 dB,
// median time): q = 40: 80.6 / 39.9, 7 ms; q = 80: 81.2 / 45.4, 27 ms; q = 120: 80.5 / 45.8,
// 55 ms; q = 200: 80.5 / 45.4, 140 ms. Cost: a QR of L x 2q (2048 x 160 for N = 2048), a
// q x q SVD and one triangular solve per point, O(L q^2).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/sysid/state_space.h"

namespace chatterlab {
namespace sysid {

struct FrequencySubspaceOptions {
  // Model order; 0: chosen by the Gavish-Donoho median rule (step 4). 0 <= order <= max_order.
  int order = 0;
  // Block rows q; 0: 2 max_order. Otherwise q >= 2 and q > order.
  int block_rows = 0;
  // Largest model order kept. >= 1.
  int max_order = 40;
};

struct FrequencySubspaceResult {
  StepSummary summary;
  DiscreteStateSpace model;         // the stable part, B and D fitted for it
  Eigen::VectorXd singular_values;  // of R22, q of them, descending
  double threshold = std::numeric_limits<double>::quiet_NaN();     // NaN when order was given
  double aspect_ratio = std::numeric_limits<double>::quiet_NaN();  // b of step 4
  int order_by_threshold = 0;  // before the caps (or the given order)
  int block_rows = 0;          // q
  int real_columns = 0;        // L
  int unstable_removed = 0;
  Eigen::VectorXcd poles;  // of model
  std::vector<DiscreteMode> modes;
  double dc_gain = std::numeric_limits<double>::quiet_NaN();
  double fit_pct = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd fit_f_hz;      // the points 0 < f <= rate/2
  Eigen::VectorXcd fit_G;        // their measured values
  Eigen::VectorXcd fit_G_model;  // and the model's
  double svd_s = 0.0;            // wall time of the QR and SVD (steps 3-4)
  double runtime_s = 0.0;
};

// Steps 1-8 on a measured FRF. @param f_hz strictly rising, 0 <= f <= rate/2 (any spacing;
// the uniform grid is the case the weighting argument of step 3 covers), with L >= 2q real
// columns (step 2); @param G the FRF at f_hz. Never throws for bad data or options: the
// summary says what failed (the InputError's message, naming the field).
FrequencySubspaceResult frequency_subspace_identify(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                                    const Eigen::Ref<const Eigen::VectorXcd>& G,
                                                    double sample_rate_hz,
                                                    const FrequencySubspaceOptions& options = {});

}  // namespace sysid
}  // namespace chatterlab
