#include "analysis/sysid/era.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <numeric>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/common/stopwatch.h"
#include "analysis/signal/fft.h"
#include "analysis/sysid/gavish_donoho.h"

// LAPACK (Fortran 77 interface; the trailing size_t arguments are the hidden lengths of the
// character arguments that gfortran passes).
extern "C" {
void dstebz_(const char* range, const char* order, const int* n, const double* vl, const double* vu,
             const int* il, const int* iu, const double* abstol, const double* d, const double* e,
             int* m, int* nsplit, double* w, int* iblock, int* isplit, double* work, int* iwork,
             int* info, std::size_t, std::size_t);
void dstein_(const int* n, const double* d, const double* e, const int* m, const double* w,
             const int* iblock, const int* isplit, double* z, const int* ldz, double* work,
             int* iwork, int* ifail, int* info);
using LapackSelect2 = int (*)(const double*, const double*);
void dgees_(const char* jobvs, const char* sort, LapackSelect2 select, const int* n, double* a,
            const int* lda, int* sdim, double* wr, double* wi, double* vs, const int* ldvs,
            double* work, const int* lwork, int* bwork, int* info, std::size_t, std::size_t);
void dtrsyl_(const char* trana, const char* tranb, const int* isgn, const int* m, const int* n,
             const double* a, const int* lda, const double* b, const int* ldb, double* c,
             const int* ldc, double* scale, int* info, std::size_t, std::size_t);
}

#include "analysis/common/statistics.h"

namespace chatterlab {
namespace sysid {
namespace {

using Clock = SteadyClock;

int select_stable(const double* wr, const double* wi) {
  return std::hypot(*wr, *wi) < kStableRadius ? 1 : 0;
}

// The r eigenpairs of largest |lambda| of the symmetric matrix H, all eigenvalues returned in
// `all` (ascending). Columns of U in order of descending |lambda|.
void symmetric_top_eigenpairs(const Eigen::MatrixXd& H, int r, Eigen::VectorXd* all,
                              Eigen::VectorXd* lambda, Eigen::MatrixXd* U, int* unconverged) {
  const int n = static_cast<int>(H.rows());
  Eigen::Tridiagonalization<Eigen::MatrixXd> tri(n);
  tri.compute(H);
  Eigen::VectorXd d = tri.diagonal();
  Eigen::VectorXd e = tri.subDiagonal();
  e.conservativeResize(std::max(n - 1, 1));
  // All eigenvalues by implicit QR on the tridiagonal matrix (values only: milliseconds);
  // the r of largest magnitude are the k_neg lowest and k_pos highest. Those are refined by
  // bisection (dstebz, by index), which also gives the split blocks dstein needs: their
  // eigenvalues grouped by block, ascending within each.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> values;
  values.computeFromTridiagonal(d, e.head(n - 1), Eigen::EigenvaluesOnly);
  if (values.info() != Eigen::Success) {
    throw std::runtime_error("the tridiagonal eigenvalue iteration did not converge");
  }
  *all = values.eigenvalues();  // ascending
  int lo = 0;
  int hi = n - 1;
  for (int k = 0; k < r; ++k) {
    if (std::abs((*all)[lo]) > std::abs((*all)[hi])) {
      ++lo;
    } else {
      --hi;
    }
  }
  const int k_neg = lo;
  const int k_pos = n - 1 - hi;
  const double zero = 0.0;
  std::vector<std::pair<int, double>> picked;  // (block, eigenvalue)
  std::vector<int> isplit(static_cast<std::size_t>(n));
  const auto bisect = [&](int il, int iu) {
    int m = 0;
    int nsplit = 0;
    int info = 0;
    Eigen::VectorXd w(n);
    std::vector<int> iblock(static_cast<std::size_t>(n));
    Eigen::VectorXd work(4 * n);
    std::vector<int> iwork(static_cast<std::size_t>(3 * n));
    dstebz_("I", "B", &n, &zero, &zero, &il, &iu, &zero, d.data(), e.data(), &m, &nsplit, w.data(),
            iblock.data(), isplit.data(), work.data(), iwork.data(), &info, 1, 1);
    if (info != 0) {
      throw std::runtime_error("LAPACK dstebz failed (info " + std::to_string(info) + ")");
    }
    for (int k = 0; k < m; ++k) picked.emplace_back(iblock[static_cast<std::size_t>(k)], w[k]);
  };
  if (k_neg > 0) bisect(1, k_neg);
  if (k_pos > 0) bisect(n - k_pos + 1, n);
  std::sort(picked.begin(), picked.end());
  r = static_cast<int>(picked.size());
  Eigen::VectorXd wsel(r);
  std::vector<int> bsel(static_cast<std::size_t>(r));
  for (int k = 0; k < r; ++k) {
    bsel[static_cast<std::size_t>(k)] = picked[static_cast<std::size_t>(k)].first;
    wsel[k] = picked[static_cast<std::size_t>(k)].second;
  }
  int info = 0;
  Eigen::MatrixXd Z(n, r);
  Eigen::VectorXd work2(5 * n);
  std::vector<int> iwork2(static_cast<std::size_t>(n)), ifail(static_cast<std::size_t>(r));
  dstein_(&n, d.data(), e.data(), &r, wsel.data(), bsel.data(), isplit.data(), Z.data(), &n,
          work2.data(), iwork2.data(), ifail.data(), &info);
  if (info < 0) {
    throw std::runtime_error("LAPACK dstein failed (info " + std::to_string(info) + ")");
  }
  *unconverged = info;  // > 0: that many eigenvectors failed to converge in 5 iterations
  const Eigen::MatrixXd Q_Z = tri.matrixQ() * Z;
  // Back into descending |lambda| order.
  std::vector<int> order(static_cast<std::size_t>(r));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return std::abs(wsel[a]) > std::abs(wsel[b]); });
  lambda->resize(r);
  U->resize(n, r);
  for (int k = 0; k < r; ++k) {
    (*lambda)[k] = wsel[order[static_cast<std::size_t>(k)]];
    U->col(k) = Q_Z.col(order[static_cast<std::size_t>(k)]);
  }
}

}  // namespace

Eigen::VectorXd markov_parameters_from_frf(const Eigen::Ref<const Eigen::VectorXd>& f,
                                           const Eigen::Ref<const Eigen::VectorXcd>& G, double rate,
                                           double grid_step_hz) {
  require_rule(std::isfinite(rate) && rate > 0.0, "sample_rate_hz", rate, "must be finite and > 0");
  const Eigen::Index n = f.size();
  require_rule(n >= 2, "freq_hz", std::to_string(n) + " points", "needs at least 2 points");
  require_rule(G.size() == n, "FRF values", G.size(), "must be as many as freq_hz");
  for (Eigen::Index i = 0; i < n; ++i) {
    require_rule(std::isfinite(f[i]), "freq_hz", f[i], "must be finite");
    require_rule(std::isfinite(G[i].real()) && std::isfinite(G[i].imag()),
                 "FRF at " + std::to_string(f[i]) + " Hz", G[i], "must be finite");
  }
  const double nyquist = 0.5 * rate;
  require_rule(f[0] >= 0.0, "freq_hz", f[0], "the first frequency must be >= 0");
  require_rule(f[n - 1] <= nyquist * (1.0 + 1e-12), "freq_hz", f[n - 1],
               "the last frequency must be <= sample_rate_hz / 2 = " + std::to_string(nyquist));
  double df = grid_step_hz;
  if (std::isnan(grid_step_hz)) {
    df = (f[n - 1] - f[0]) / static_cast<double>(n - 1);
    require_rule(df > 0.0, "freq_hz", f[n - 1], "must rise");
    // The reference step is the median step, so that the message names the odd point.
    Eigen::VectorXd steps = f.tail(n - 1) - f.head(n - 1);
    std::sort(steps.data(), steps.data() + steps.size());
    const double typical = steps[steps.size() / 2];
    for (Eigen::Index i = 1; i < n; ++i) {
      const double step = f[i] - f[i - 1];
      if (!(std::abs(step - typical) <= 1e-3 * typical)) {
        std::ostringstream m;
        m << "freq_hz = " << f[i] << " after " << f[i - 1]
          << ": the step must be uniform (within 0.1 % of the typical step " << typical << " Hz)";
        throw InputError(m.str());
      }
    }
  } else {
    require_rule(std::isfinite(df) && df > 0.0, "grid step", df, "must be > 0");
    for (Eigen::Index i = 1; i < n; ++i) {
      if (!(f[i] > f[i - 1])) {
        std::ostringstream m;
        m << "freq_hz = " << f[i] << " after " << f[i - 1] << ": the frequencies must rise";
        throw InputError(m.str());
      }
    }
  }
  const double half_steps = rate / (2.0 * df);
  require_rule(std::isfinite(half_steps) && half_steps <= 1e7, "freq_hz step", df,
               "too fine for the rate: sample_rate_hz / (2 step) must be <= 1e7 grid points");
  const long M = std::lround(half_steps);
  require_rule(M >= 4, "freq_hz step", df,
               "too coarse for the rate: sample_rate_hz / (2 step) must be >= 4");
  const Eigen::Index N = 2 * M;
  Eigen::VectorXcd X(M + 1);
  const double f_last = f[n - 1];
  Eigen::Index i = 0;  // f[i] <= fm < f[i + 1] while fm is inside the data (fm rises)
  for (long m = 0; m <= M; ++m) {
    // The last grid point is rate/2 exactly (m rate / N can round one ulp above it).
    const double fm = m == M ? nyquist : static_cast<double>(m) * rate / static_cast<double>(N);
    std::complex<double> v;
    if (fm <= f[0]) {
      v = G[0];
    } else if (fm <= f_last) {
      while (i < n - 2 && f[i + 1] < fm) ++i;
      const double t = (fm - f[i]) / (f[i + 1] - f[i]);
      v = G[i] + t * (G[i + 1] - G[i]);
    } else if (nyquist > f_last) {
      v = G[n - 1] * 0.5 * (1.0 + std::cos(kPi * (fm - f_last) / (nyquist - f_last)));
    } else {
      v = G[n - 1];  // f_last is rate/2 within rounding
    }
    X[m] = v;
  }
  X[M] = X[M].real();
  signal::RealFft fft(N);
  Eigen::VectorXd y = fft.inverse(X);  // imaginary parts of bins 0 and M ignored (Re IDFT)
  y /= static_cast<double>(N);
  return y;
}

EraRealization era_realize(const Eigen::Ref<const Eigen::VectorXd>& y, double rate,
                           const EraOptions& options) {
  require_rule(options.max_order >= 1, "era_max_order", options.max_order, "must be >= 1");
  require_rule(options.max_hankel_size >= 2, "max_hankel_size", options.max_hankel_size,
               "must be >= 2");
  require_rule(std::isnan(options.markov_noise_std) ||
                   (std::isfinite(options.markov_noise_std) && options.markov_noise_std > 0.0),
               "markov_noise_std", options.markov_noise_std, "must be NaN (unknown) or > 0");
  require_rule(y.size() >= 8, "Markov parameters", std::to_string(y.size()) + " samples",
               "needs at least 8");
  require_rule(y.allFinite(), "Markov parameters", "a non-finite value", "must all be finite");
  EraRealization out;
  const int alpha = static_cast<int>(std::min<Eigen::Index>(y.size() / 4, options.max_hankel_size));
  out.hankel_size = alpha;
  Eigen::MatrixXd H(alpha, alpha);
  for (int j = 0; j < alpha; ++j) H.col(j) = y.segment(j + 1, alpha);
  const auto t0 = Clock::now();
  // All eigenvalues first (for the threshold); then the vectors of the kept ones.
  Eigen::VectorXd all;
  Eigen::VectorXd lambda;
  Eigen::MatrixXd U;
  // The order is not known before the eigenvalues are; ask for the cap and keep the first r.
  const int want = std::min(options.max_order, alpha - 1);
  int unconverged = 0;
  symmetric_top_eigenpairs(H, want, &all, &lambda, &U, &unconverged);
  out.svd_s = seconds_since(t0);
  out.singular_values = all.cwiseAbs();
  std::sort(out.singular_values.data(), out.singular_values.data() + alpha, std::greater<double>());
  const double s1 = out.singular_values[0];
  const double floor = alpha * std::numeric_limits<double>::epsilon() * s1;
  const double rule = std::isnan(options.markov_noise_std)
                          ? kEraMedianRuleOmega * median(out.singular_values)
                          : gavish_donoho_lambda(1.0) * std::sqrt(static_cast<double>(alpha)) *
                                options.markov_noise_std;
  out.threshold = std::max(rule, floor);
  int r = 0;
  while (r < alpha && out.singular_values[r] > out.threshold) ++r;
  out.order_by_threshold = r;
  r = std::min({r, want, static_cast<int>(lambda.size())});
  if (r == 0) {
    std::ostringstream m;
    m << "ERA kept no state: the largest singular value " << s1 << " is not above the threshold "
      << out.threshold;
    out.summary.fail(m.str());
    return out;
  }
  const Eigen::VectorXd s = lambda.head(r).cwiseAbs();
  const Eigen::MatrixXd Ur = U.leftCols(r);
  Eigen::MatrixXd Vr = Ur;
  for (int k = 0; k < r; ++k) {
    if (lambda[k] < 0.0) Vr.col(k) = -Vr.col(k);
  }
  Eigen::MatrixXd Hp(alpha, alpha);
  for (int j = 0; j < alpha; ++j) Hp.col(j) = y.segment(j + 2, alpha);
  const Eigen::VectorXd s_inv_half = s.cwiseSqrt().cwiseInverse();
  const Eigen::VectorXd s_half = s.cwiseSqrt();
  DiscreteStateSpace& model = out.model;
  model.sample_rate_hz = rate;
  model.A = s_inv_half.asDiagonal() * (Ur.transpose() * (Hp * Vr)) * s_inv_half.asDiagonal();
  model.B = s_half.asDiagonal() * Vr.row(0).transpose();
  model.C = Ur.row(0) * s_half.asDiagonal();
  model.D = y[0];
  out.summary.succeed();
  if (unconverged > 0) {
    out.summary.warnings.push_back(std::to_string(unconverged) +
                                   " Hankel eigenvectors did not converge (LAPACK dstein): the "
                                   "realization may be inaccurate");
  }
  if (out.order_by_threshold > r) {
    std::ostringstream m;
    m << "the threshold kept " << out.order_by_threshold
      << " singular values; the order is capped at " << r;
    out.summary.warnings.push_back(m.str());
  }
  return out;
}

StableSplit stable_part(const DiscreteStateSpace& model) {
  StableSplit out;
  const int n = static_cast<int>(model.order());
  out.stable.sample_rate_hz = model.sample_rate_hz;
  out.stable.D = model.D;
  if (n == 0) {
    out.stable = model;
    out.decoupling_residual = 0.0;
    out.summary.succeed();
    return out;
  }
  Eigen::MatrixXd T_A = model.A;  // overwritten by the Schur form
  Eigen::MatrixXd Z(n, n);
  Eigen::VectorXd wr(n), wi(n);
  std::vector<int> bwork(static_cast<std::size_t>(n));
  int sdim = 0;
  int info = 0;
  const int lwork = std::max(1, 8 * n);
  Eigen::VectorXd work(lwork);
  dgees_("V", "S", &select_stable, &n, T_A.data(), &n, &sdim, wr.data(), wi.data(), Z.data(), &n,
         work.data(), &lwork, bwork.data(), &info, 1, 1);
  if (info != 0 && info != n + 2) {
    out.summary.fail("the ordered Schur form failed (LAPACK dgees info " + std::to_string(info) +
                     ")");
    return out;
  }
  if (info == n + 2) {
    out.summary.warnings.push_back(
        "rounding moved a pole across |z| = 1 - 1e-9 while the Schur form was reordered");
  }
  const int ns = sdim;
  const int nu = n - ns;
  out.removed = nu;
  const Eigen::VectorXd B_sep = Z.transpose() * model.B;
  const Eigen::RowVectorXd C_sep = model.C * Z;
  if (nu == 0) {
    out.stable.A = T_A;
    out.stable.B = B_sep;
    out.stable.C = C_sep;
    out.decoupling_residual = 0.0;
    out.summary.succeed();
    return out;
  }
  if (ns == 0) {
    out.stable.A.resize(0, 0);
    out.stable.B.resize(0);
    out.stable.C.resize(0);
    out.decoupling_residual = 0.0;
    out.summary.succeed();
    out.summary.warnings.push_back("every pole is unstable: the stable part is the constant D");
    return out;
  }
  const Eigen::MatrixXd A11 = T_A.topLeftCorner(ns, ns);
  const Eigen::MatrixXd A12 = T_A.topRightCorner(ns, nu);
  const Eigen::MatrixXd A22 = T_A.bottomRightCorner(nu, nu);
  // A11 S - S A22 = -A12 (dtrsyl: op(A) X + isgn X op(B) = scale C, with A, B quasi-triangular).
  Eigen::MatrixXd S = -A12;
  const int isgn = -1;
  double scale = 1.0;
  dtrsyl_("N", "N", &isgn, &ns, &nu, A11.data(), &ns, A22.data(), &nu, S.data(), &ns, &scale, &info,
          1, 1);
  if (info < 0) {
    out.summary.fail("the Sylvester solve failed (LAPACK dtrsyl info " + std::to_string(info) +
                     ")");
    return out;
  }
  if (scale != 1.0) S /= scale;
  if (info == 1) {
    out.summary.warnings.push_back(
        "the stable and unstable parts share nearly equal poles: the Sylvester solve was "
        "perturbed");
  }
  // W = [I S; 0 I]; W^-1 A_sep W = [A11, A11 S + A12 - S A22; 0, A22].
  const Eigen::MatrixXd off = A11 * S + A12 - S * A22;
  const double norm_a = std::max(model.A.norm(), std::numeric_limits<double>::min());
  out.decoupling_residual = off.cwiseAbs().maxCoeff() / norm_a;
  out.stable.A = A11;
  out.stable.B = B_sep.head(ns) - S * B_sep.tail(nu);
  out.stable.C = C_sep.head(ns);
  out.summary.succeed();
  return out;
}

double frf_fit_pct(const Eigen::Ref<const Eigen::VectorXcd>& G,
                   const Eigen::Ref<const Eigen::VectorXcd>& G_model) {
  require_rule(G.size() == G_model.size(), "model FRF", G_model.size(),
               "must have as many points as the measured FRF");
  require_rule(G.size() >= 2, "FRF", std::to_string(G.size()) + " points", "needs at least 2");
  const std::complex<double> mean = G.mean();
  const double den = (G.array() - mean).matrix().norm();
  return 100.0 * (1.0 - (G - G_model).norm() / den);
}

EraResult era_identify(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                       const Eigen::Ref<const Eigen::VectorXcd>& G, double rate,
                       const EraOptions& options) {
  EraResult out;
  const auto t0 = Clock::now();
  try {
    const Eigen::VectorXd y = markov_parameters_from_frf(f_hz, G, rate, options.grid_step_hz);
    out.markov_length = static_cast<int>(y.size());
    out.realization = era_realize(y, rate, options);
    if (!out.realization.summary.ok()) {
      out.summary.fail(out.realization.summary.message);
      out.runtime_s = seconds_since(t0);
      return out;
    }
    const StableSplit split = stable_part(out.realization.model);
    if (!split.summary.ok()) {
      out.summary.fail(split.summary.message);
      out.runtime_s = seconds_since(t0);
      return out;
    }
    out.model = split.stable;
    out.unstable_removed = split.removed;
    out.decoupling_residual = split.decoupling_residual;
    out.poles = poles(out.model);
    out.modes = modes_of(out.poles, rate);
    out.dc_gain = dc_gain(out.model);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
      if (f_hz[i] > 0.0 && f_hz[i] <= 0.5 * rate * (1.0 + 1e-12)) keep.push_back(i);
    }
    out.fit_f_hz.resize(static_cast<Eigen::Index>(keep.size()));
    out.fit_G.resize(out.fit_f_hz.size());
    for (std::size_t k = 0; k < keep.size(); ++k) {
      out.fit_f_hz[static_cast<Eigen::Index>(k)] = f_hz[keep[k]];
      out.fit_G[static_cast<Eigen::Index>(k)] = G[keep[k]];
    }
    out.fit_G_model = frequency_response(out.model, out.fit_f_hz);
    out.fit_pct = frf_fit_pct(out.fit_G, out.fit_G_model);
    out.summary.succeed();
    for (const auto& w : out.realization.summary.warnings) out.summary.warnings.push_back(w);
    for (const auto& w : split.summary.warnings) out.summary.warnings.push_back(w);
  } catch (const InputError& e) {
    out.summary.fail(e.what());
  } catch (const std::runtime_error& e) {
    out.summary.fail(e.what());
  }
  out.runtime_s = seconds_since(t0);
  return out;
}

}  // namespace sysid
}  // namespace chatterlab
