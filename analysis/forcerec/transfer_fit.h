// The dynamometer's transfer function of one axis (004 sec. 3.1), fitted to a measured FRF:
//
//   G(s) = (b1 s^(n-1) + b2 s^(n-2) + ... + bn) / (s^n + a1 s^(n-1) + ... + an)     (004 eq. 3.1)
//
// denominator order n (even, default 6: "6-DOF" in 004 means 6th order, notes/004.md E14),
// numerator order n - 1 (relative degree one, b1 != 0), stable poles and minimum phase (all
// zeros in the left half plane): the sliding-mode observer of 004 eqs 2.12-2.22 needs both.
//
// 004 fits with MATLAB's System Identification Toolbox and then tunes poles and zeros "manually"
// until the model is minimum phase; neither step is reproducible, so the fit here is:
//  1. Vector fitting (Gustavsen & Semlyen 1999, with the relaxed sigma of Gustavsen 2006) of the
//     strictly proper partial fractions sum_k r_k / (s - p_k) on the band's samples, in the
//     scaled variable s~ = s / w_ref, w_ref = 2 pi f_max of the band (every number O(1): the
//     polynomial coefficients of Table 3.1 span 1e3..1e24). Starting poles: n/2 pairs
//     -w/100 +- j w, w evenly spread over the band; complex pairs in the real formulation;
//     unstable poles flipped into the left half plane at every iteration.
//  2. Zeros from the zero dynamics of the partial-fraction realization; a right-half-plane
//     zero z is mirrored to -conj(z), which keeps |G(jw)| exactly (|jw - z| = |jw + conj z|);
//     then the real gain is refitted by linear least squares.
//  3. Ceres Levenberg-Marquardt on the factored form G = k prod(s~ - z~) / prod(s~ - p~) over
//     a parametrization that is stable and minimum phase by construction: each pole pair and
//     each zero pair is a factor s~^2 + 2 zeta wn s~ + wn^2 with wn = e^u, zeta = e^v (> 0:
//     Hurwitz; zeta >= min_zeta by a bound), each real pole or zero a factor s~ + e^q.
//     Automatic derivatives. A zero mirrored in step 2 is where the data put it in the right
//     half plane: the complex refinement then trades some magnitude fit for phase (on Hyy with
//     its 1722 Hz zero pair moved to the right half plane, fit % 100 -> 95; the test) and
//     usually leaves the pair on the damping floor, with a warning.
// The cost is sum_i w_i^2 |H_i - G(j w_i)|^2. Default w_i = 1: maximum likelihood for noise of
// one variance on every bin, and exactly the error that fit % (004 eq. 3.2) measures. The
// option kRelative (w_i = 1 / |H_i|) weights the antiresonances (the zeros, which are the
// eigenvalues of the observer's A11) like the peaks; use it when noise is proportional to |H|.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/forcerec/model.h"

namespace chatterlab {
namespace forcerec {

// A pair s, conj(s) of roots of a real polynomial: a pole pair or a zero pair.
struct RootPair {
  std::complex<double> s;                                   // rad/s, Im s > 0
  double fn_hz = std::numeric_limits<double>::quiet_NaN();  // |s| / (2 pi)
  double zeta = std::numeric_limits<double>::quiet_NaN();   // -Re s / |s|; > 0: left half plane
};

// 004 eq. 3.1 in factored form, G(s) = b1 prod_i (s - z_i) / prod_j (s - p_j): n poles, n - 1
// zeros (relative degree one). Conjugate roots are held once, as a RootPair.
struct TransferModel {
  std::vector<RootPair> pole_pairs;      // by fn_hz
  std::vector<double> real_poles_rad_s;  // by |p|
  std::vector<RootPair> zero_pairs;      // by fn_hz
  std::vector<double> real_zeros_rad_s;  // by |z|
  // High-frequency gain (1/s): G(s) -> b1 / s as |s| -> infinity; b1 = C B of any realization.
  double b1 = std::numeric_limits<double>::quiet_NaN();

  int order() const;               // n, the number of poles
  Eigen::VectorXcd poles() const;  // all n, rad/s (each pair as s, conj s)
  Eigen::VectorXcd zeros() const;  // all n - 1, rad/s
};

// A model from its roots (rad/s). @param poles n >= 1 roots, @param zeros n - 1 roots, complex
// ones in conjugate pairs (matched within 1e-9 |s|); @param b1 finite, non-zero.
// @throws InputError naming the argument and the rule it broke.
TransferModel transfer_model_from_roots(const Eigen::Ref<const Eigen::VectorXcd>& poles,
                                        const Eigen::Ref<const Eigen::VectorXcd>& zeros, double b1);

// A model from 004 eq. 3.1's coefficients as 004 Table 3.1 lists them: num = [b1 .. bn],
// den = [a1 .. an] (the leading 1 of s^n left out; units s^-i). Roots are the eigenvalues of the
// companion matrices of the frequency-scaled polynomials (s = w0 s~, w0 = max_i |c_i|^(1/i) over
// each polynomial's coefficients c_i).
// @throws InputError for sizes that differ, n < 1, b1 = 0 or a coefficient not finite.
TransferModel transfer_model_from_coefficients(const Eigen::Ref<const Eigen::VectorXd>& num,
                                               const Eigen::Ref<const Eigen::VectorXd>& den);

// [b1 .. bn] and [a1 .. an] of 004 eq. 3.1 (units s^-i), expanded from the roots.
Eigen::VectorXd numerator_coefficients(const TransferModel& model);
Eigen::VectorXd denominator_coefficients(const TransferModel& model);

// G(0) = bn / an.
double dc_gain(const TransferModel& model);

// G(j 2 pi f) from the factored form.
std::complex<double> transfer_response(const TransferModel& model, double f_hz);
Eigen::VectorXcd transfer_response(const TransferModel& model,
                                   const Eigen::Ref<const Eigen::VectorXd>& f_hz);

// Zeros with Re z > 0 (each root of a pair counted).
int rhp_zero_count(const TransferModel& model);
// Every right-half-plane zero z replaced by -conj(z): |G(j w)| unchanged at every w, the
// phase changed; the result is minimum phase (a zero on the imaginary axis stays there).
TransferModel mirror_rhp_zeros(const TransferModel& model);

// The scaled real modal realization of a model with distinct poles (not the controllable
// canonical form of 004 eq. 3.4, whose 2-norm condition number is 3e23-9e23 with Table 3.1; nor
// 004 eq. 3.5, whose T is never given). G(s) = sum_j r_j / (s - p_j) with residues
// r_j = b1 prod_i (p_j - z_i) / prod_{l != j} (p_j - p_l); block diagonal, in pair order then
// real poles:
//   pair p = sigma + j omega, r = r' + j r'':  A_k = [[sigma, omega], [-omega, sigma]],
//     B_k = [beta, 0]^T, C_k = [2 r' / beta, 2 r'' / beta], beta = sqrt(2 |r|);
//   real pole p, residue r:  A_k = p, B_k = sqrt|r|, C_k = r / sqrt|r|.
// Each A_k is a scaled rotation (a normal matrix), so cond_2(A) = max|p| / min|p|, and
// |B_k| = |C_k| (the gain split evenly between input and output).
// @throws InputError when two poles coincide within 1e-9 |p| (no diagonal form).
ContinuousModel realize_scaled_modal(const TransferModel& model);

// The 2-norm condition number sigma_max / sigma_min by the SVD (infinity for a singular
// matrix): meaningful only well below 1 / eps (~4.5e15); the SVD's absolute error eps sigma_max
// swamps sigma_min beyond (e.g. the canonical form of 004 eq. 3.4).
double condition_number(const Eigen::Ref<const Eigen::MatrixXd>& A);

enum class FitWeighting {
  kUniform,   // w_i = 1: the error fit % (004 eq. 3.2) measures
  kRelative,  // w_i = 1 / |H_i|: relative error, antiresonances weighted like peaks
};

struct TransferFitOptions {
  int order = 6;  // n of 004 eq. 3.1: even, >= 2 (numerator n - 1)
  // Fit band [lo, hi] in Hz, inclusive; NaN: the lowest / highest frequency of the data. 004
  // gives only the upper limit, 1.6e4 rad/s (2546 Hz); the lower one is not stated (E14).
  double band_lo_hz = std::numeric_limits<double>::quiet_NaN();
  double band_hi_hz = std::numeric_limits<double>::quiet_NaN();
  FitWeighting weighting = FitWeighting::kUniform;
  int vf_max_iterations = 30;  // pole relocations of vector fitting, >= 1
  // Vector fitting stops when no pole moves by more than this x |p| in one relocation.
  double vf_pole_tolerance = 1e-10;
  int refine_max_iterations = 200;  // Levenberg-Marquardt iterations of step 3; 0: no refinement
  // Step 3 keeps every pole pair's and zero pair's damping ratio >= min_zeta (a bound of the
  // log parametrization), so that the model is strictly stable and strictly minimum phase: data
  // that want a zero in the right half plane otherwise drive its pair onto the imaginary axis,
  // where the observer's error e1 (eigenvalues of A11 = the zeros, notes/004.md sec. 5) would
  // never decay. 1e-3 is 15x below the lightest damping in 004 Table 3.1 (0.0150); with it the
  // slowest possible decay of e1 at 1 kHz is 6.3 rad/s. In (0, 1).
  double min_zeta = 1e-3;
};

struct TransferFit {
  StepSummary summary;
  TransferModel model;  // stable, minimum phase, relative degree one
  Eigen::VectorXd num;  // [b1 .. bn] (004 eq. 3.1, units s^-i)
  Eigen::VectorXd den;  // [a1 .. an] (monic denominator, units s^-i)
  double dc_gain = std::numeric_limits<double>::quiet_NaN();  // bn / an
  // 004 eq. 3.2 over the band's complex samples: 100 (1 - ||H - G|| / ||H - mean H||), complex
  // mean, Euclidean norms of the complex vectors (metrics::nrmse_fit_pct), unweighted whatever
  // the weighting of the fit.
  double fit_pct = std::numeric_limits<double>::quiet_NaN();
  double vf_fit_pct = std::numeric_limits<double>::quiet_NaN();  // after step 1, before 2-3
  int vf_iterations = 0;
  int refine_iterations = 0;
  int poles_flipped = 0;        // unstable poles flipped during vector fitting (all iterations)
  int zeros_mirrored = 0;       // right-half-plane zeros mirrored in step 2 (each root counted)
  ContinuousModel realization;  // realize_scaled_modal(model)
  double realization_cond_A = std::numeric_limits<double>::quiet_NaN();
  double band_lo_hz = 0.0;  // the band used (the data's points inside the options' band)
  double band_hi_hz = 0.0;
  Eigen::VectorXd f_hz;  // the band's samples
  Eigen::VectorXcd H;    // measured
  Eigen::VectorXcd G;    // model
};

// @param f_hz frequencies (Hz), finite and >= 0, any order; @param H the FRF at f_hz.
// @throws InputError for sizes that differ, non-finite data, bad options, fewer than 2 n points
// in the band, or (kRelative) H = 0 in the band. A numerical failure (relative degree above one,
// coinciding poles) is reported by the summary.
TransferFit fit_transfer_function(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                  const Eigen::Ref<const Eigen::VectorXcd>& H,
                                  const TransferFitOptions& options = {});

}  // namespace forcerec
}  // namespace chatterlab
