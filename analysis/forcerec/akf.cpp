#include "analysis/forcerec/akf.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "analysis/common/require.h"
#include "analysis/kalman/dare.h"

namespace chatterlab {
namespace forcerec {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// The modal kernels keep their state in fixed arrays: n + 1 <= kMaxModalStates (n ~ 12 in
// practice); larger models run the dense form.
constexpr int kMaxModalStates = 64;

void check_model(const DiscreteModel& m) {
  const Index n = m.Ad.rows();
  if (n < 1 || m.Ad.cols() != n || m.Bd.size() != n || m.C.size() != n) {
    throw std::invalid_argument(
        "akf: the model must have a square Ad (n >= 1), Bd of n rows and C of n columns");
  }
}

// The real block-diagonal modal form of f.Phi (see AkfFilter), or false when Phi's eigenvectors
// are too ill-conditioned for it (then the dense form runs).
bool modal_form(AkfFilter& f, Index m) {
  if (m > kMaxModalStates) return false;
  const Eigen::EigenSolver<MatrixXd> es(f.Phi);
  if (es.info() != Eigen::Success) return false;
  const Eigen::VectorXcd lam = es.eigenvalues();
  const Eigen::MatrixXcd V = es.eigenvectors();
  MatrixXd T(m, m);
  Index col = 0;
  int pairs = 0;
  // Pairs first (one per conjugate pair: Im > 0), then the real eigenvalues.
  for (Index i = 0; i < m; ++i) {
    const double tol = 1e-12 * std::max(std::abs(lam[i]), 1e-300);
    if (lam[i].imag() > tol) {
      if (col + 2 > m) return false;
      T.col(col++) = V.col(i).real();
      T.col(col++) = V.col(i).imag();
      ++pairs;
    }
  }
  for (Index i = 0; i < m; ++i) {
    const double tol = 1e-12 * std::max(std::abs(lam[i]), 1e-300);
    if (std::abs(lam[i].imag()) <= tol) {
      if (col + 1 > m) return false;
      T.col(col++) = V.col(i).real();
    }
  }
  if (col != m) return false;
  const Eigen::PartialPivLU<MatrixXd> lu(T);
  // rcond > 1e-10: the modal coordinates lose at most ~10 of the 16 digits.
  if (!(lu.rcond() > 1e-10)) return false;
  const MatrixXd Lam = lu.solve(f.Phi * T);
  MatrixXd Lb = MatrixXd::Zero(m, m);
  VectorXd diag(m), off(pairs);
  for (int j = 0; j < pairs; ++j) {
    // Phi [vr vi] = [vr vi] [[p, q], [-q, p]] for the eigenvalue p + j q, q > 0.
    const double p = 0.5 * (Lam(2 * j, 2 * j) + Lam(2 * j + 1, 2 * j + 1));
    const double q = 0.5 * (Lam(2 * j, 2 * j + 1) - Lam(2 * j + 1, 2 * j));
    diag[2 * j] = diag[2 * j + 1] = p;
    off[j] = q;
    Lb(2 * j, 2 * j) = Lb(2 * j + 1, 2 * j + 1) = p;
    Lb(2 * j, 2 * j + 1) = q;
    Lb(2 * j + 1, 2 * j) = -q;
  }
  for (Index i = 2 * pairs; i < m; ++i) diag[i] = Lb(i, i) = Lam(i, i);
  const double scale = std::max(f.Phi.norm() * T.norm(), 1e-300);
  f.modal_residual = (T * Lb - f.Phi * T).norm() / scale;
  // 1e-10: the blocks reproduce Phi to ~1e-10 relative (rounding of the eigen-decomposition is
  // ~1e-15 times the eigenvector condition number, which rcond bounds).
  if (!(f.modal_residual < 1e-10)) return false;
  f.modal = true;
  f.pairs = pairs;
  f.diag = diag;
  f.off = off;
  f.b = lu.solve(f.L);
  f.g = f.G_a * T;
  f.h = f.h * T;
  return true;
}

// ---- Kernels. P pairs and S1 scalars at compile time (-1: at run time, from the filter).

template <int P, int S1>
struct Modal {
  int np, ns;
  std::array<double, kMaxModalStates / 2> p{}, q{}, b1{}, b2{}, g1{}, g2{}, h1{}, h2{};
  std::array<double, kMaxModalStates> a{}, bs{}, gs{}, hs{};
  // Fixed counts may exceed the filter's (zero padding: even counts let the compiler use SIMD).
  explicit Modal(const AkfFilter& f) {
    const int ap = f.pairs, as = static_cast<int>(f.diag.size()) - 2 * f.pairs;
    np = P >= 0 ? P : ap;
    ns = S1 >= 0 ? S1 : as;
    for (int j = 0; j < ap; ++j) {
      p[j] = f.diag[2 * j];
      q[j] = f.off[j];
      b1[j] = f.b[2 * j];
      b2[j] = f.b[2 * j + 1];
      g1[j] = f.g[2 * j];
      g2[j] = f.g[2 * j + 1];
      h1[j] = f.h[2 * j];
      h2[j] = f.h[2 * j + 1];
    }
    for (int j = 0; j < as; ++j) {
      a[j] = f.diag[2 * ap + j];
      bs[j] = f.b[2 * ap + j];
      gs[j] = f.g[2 * ap + j];
      hs[j] = f.h[2 * ap + j];
    }
  }
  int pairs() const { return P >= 0 ? P : np; }
  int scalars() const { return S1 >= 0 ? S1 : ns; }
};

template <int P, int S1>
void modal_pass(const AkfFilter& f, const double* y, Index N, double* out, double kF) {
  const Modal<P, S1> c(f);
  const int np = c.pairs(), ns = c.scalars();
  std::array<double, kMaxModalStates / 2> w1{}, w2{};
  std::array<double, kMaxModalStates> ws{};
  for (Index k = 0; k + 1 < N; ++k) {
    const double u = y[k];
    double o = kF * y[k + 1];
    for (int j = 0; j < np; ++j) {
      const double n1 = c.p[j] * w1[j] + c.q[j] * w2[j] + c.b1[j] * u;
      const double n2 = c.p[j] * w2[j] - c.q[j] * w1[j] + c.b2[j] * u;
      w1[j] = n1;
      w2[j] = n2;
      o += c.h1[j] * n1 + c.h2[j] * n2;
    }
    for (int j = 0; j < ns; ++j) {
      ws[j] = c.a[j] * ws[j] + c.bs[j] * u;
      o += c.hs[j] * ws[j];
    }
    out[k] = o;
  }
}

template <int P, int S1>
double modal_error(const AkfFilter& f, const double* y, Index begin, Index from, Index end) {
  const Modal<P, S1> c(f);
  const int np = c.pairs(), ns = c.scalars();
  std::array<double, kMaxModalStates / 2> w1{}, w2{};
  std::array<double, kMaxModalStates> ws{};
  auto step = [&](double u) {
    for (int j = 0; j < np; ++j) {
      const double n1 = c.p[j] * w1[j] + c.q[j] * w2[j] + c.b1[j] * u;
      const double n2 = c.p[j] * w2[j] - c.q[j] * w1[j] + c.b2[j] * u;
      w1[j] = n1;
      w2[j] = n2;
    }
    for (int j = 0; j < ns; ++j) ws[j] = c.a[j] * ws[j] + c.bs[j] * u;
  };
  for (Index k = begin; k < from; ++k) step(y[k]);  // the skipped start-up
  double sum = 0.0;
  for (Index k = from; k < end; ++k) {
    const double u = y[k];
    double e = u;  // the a-priori innovation y(k) - G_a z(k|k-1)
    for (int j = 0; j < np; ++j) e -= c.g1[j] * w1[j] + c.g2[j] * w2[j];
    for (int j = 0; j < ns; ++j) e -= c.gs[j] * ws[j];
    sum += e * e;
    step(u);
  }
  return std::sqrt(sum);
}

template <int M>
void dense_pass(const AkfFilter& f, const double* y, Index N, double* out, double kF) {
  using Mat = Eigen::Matrix<double, M, M>;
  using Vec = Eigen::Matrix<double, M, 1>;
  using Row = Eigen::Matrix<double, 1, M>;
  const Mat Phi = f.Phi;
  const Vec b = f.b;
  const Row h = f.h;
  Vec z = Vec::Zero(f.b.size());
  Vec zn(f.b.size());
  for (Index k = 0; k + 1 < N; ++k) {
    zn.noalias() = Phi * z;
    zn += b * y[k];
    z = zn;
    out[k] = h.dot(z) + kF * y[k + 1];
  }
}

template <int M>
double dense_error(const AkfFilter& f, const double* y, Index begin, Index from, Index end) {
  using Mat = Eigen::Matrix<double, M, M>;
  using Vec = Eigen::Matrix<double, M, 1>;
  using Row = Eigen::Matrix<double, 1, M>;
  const Mat Phi = f.Phi;
  const Vec b = f.b;
  const Row g = f.g;
  Vec z = Vec::Zero(f.b.size());
  Vec zn(f.b.size());
  double sum = 0.0;
  for (Index k = begin; k < end; ++k) {
    const double e = y[k] - g.dot(z);
    if (k >= from) sum += e * e;
    zn.noalias() = Phi * z;
    zn += b * y[k];
    z = zn;
  }
  return std::sqrt(sum);
}

// Dispatch: fixed block counts for the modal forms of n <= 8 with at most 4 real closed-loop
// poles (the usual ones), fixed-size dense forms for n + 1 = 3, 5, 7, 9, run-time sizes otherwise.
template <class ModalFn, class DenseFn>
auto dispatch(const AkfFilter& f, ModalFn modal, DenseFn dense) {
  const int m = static_cast<int>(f.b.size());
  if (f.modal) {
    // Counts padded to even (zero blocks): the compiler then runs two blocks per SIMD operation.
    const int p = f.pairs, s = m - 2 * f.pairs;
    using std::integral_constant;
    if (p <= 2 && s <= 2) return modal(integral_constant<int, 2>{}, integral_constant<int, 2>{});
    if (p <= 2 && s <= 4) return modal(integral_constant<int, 2>{}, integral_constant<int, 4>{});
    if (p <= 4 && s <= 2) return modal(integral_constant<int, 4>{}, integral_constant<int, 2>{});
    if (p <= 4 && s <= 4) return modal(integral_constant<int, 4>{}, integral_constant<int, 4>{});
    return modal(integral_constant<int, -1>{}, integral_constant<int, -1>{});
  }
  switch (m) {
    case 3:
      return dense(std::integral_constant<int, 3>{});
    case 5:
      return dense(std::integral_constant<int, 5>{});
    case 7:
      return dense(std::integral_constant<int, 7>{});
    case 9:
      return dense(std::integral_constant<int, 9>{});
    default:
      return dense(std::integral_constant<int, Eigen::Dynamic>{});
  }
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void validate(const AkfOptions& o) {
  require_rule(std::isfinite(o.S_min_N2) && o.S_min_N2 > 0.0, "akf.S_min_N2", o.S_min_N2,
               "must be finite and > 0");
  require_rule(std::isfinite(o.S_max_N2) && o.S_max_N2 >= o.S_min_N2, "akf.S_max_N2", o.S_max_N2,
               "must be finite and >= akf.S_min_N2");
  require_rule(o.S_per_decade >= 1 && o.S_per_decade <= 1000, "akf.S_per_decade", o.S_per_decade,
               "must be in 1..1000");
  require_rule(std::isfinite(o.knee_tolerance) && o.knee_tolerance >= 0.0, "akf.knee_tolerance",
               o.knee_tolerance, "must be finite and >= 0");
  require_rule(std::isfinite(o.dip_tolerance) && o.dip_tolerance >= 0.0, "akf.dip_tolerance",
               o.dip_tolerance, "must be finite and >= 0");
  require_rule(std::isfinite(o.skip_s) && o.skip_s >= 0.0, "akf.skip_s", o.skip_s,
               "must be finite and >= 0");
  require_rule(std::isfinite(o.tuning_length_s) && o.tuning_length_s > 0.0, "akf.tuning_length_s",
               o.tuning_length_s, "must be finite and > 0");
}

// "" when y is finite, else the first bad sample.
std::string non_finite(const Eigen::Ref<const VectorXd>& y) {
  if (y.allFinite()) return "";
  for (Index k = 0; k < y.size(); ++k) {
    if (!std::isfinite(y[k])) return "y[" + std::to_string(k) + "] = " + number(y[k]);
  }
  return "";
}

// The checks both reconstructions share; false (and the summary failed) on bad data.
bool check_data(const DiscreteModel& model, const Eigen::Ref<const VectorXd>& y, double R,
                AkfResult& r) {
  check_model(model);
  if (y.size() < 2) throw std::invalid_argument("akf: y must hold at least 2 samples");
  r.R_N2 = R;
  if (!(std::isfinite(R) && R > 0.0)) {
    r.summary.fail("akf: R_N2 = " + number(R) + ": must be finite and > 0 (the noise variance)");
    return false;
  }
  const std::string bad = non_finite(y);
  if (!bad.empty()) {
    r.summary.fail("akf: " + bad + ": every sample must be finite");
    return false;
  }
  return true;
}

void finish(const AkfFilter& f, const Eigen::Ref<const VectorXd>& y, AkfResult& r) {
  r.S_N2 = f.S_N2;
  r.spectral_radius = f.spectral_radius;
  r.modal = f.modal;
  run_akf(f, y, &r.force);
  if (!r.force.allFinite()) {
    r.force.resize(0);
    r.summary.fail("akf: the reconstructed force is not finite (S_N2 = " + number(f.S_N2) + ")");
    return;
  }
  if (!f.modal) {
    r.summary.warnings.push_back(
        "akf: the filter's eigenvectors are ill-conditioned: it ran in its dense form");
  }
  r.summary.succeed();
}

}  // namespace

AkfFilter design_akf(const DiscreteModel& model, double S, double R) {
  check_model(model);
  AkfFilter f;
  f.S_N2 = S;
  f.R_N2 = R;
  if (!(std::isfinite(S) && S > 0.0)) {
    f.summary.fail("akf: S_N2 = " + number(S) + ": must be finite and > 0");
    return f;
  }
  if (!(std::isfinite(R) && R > 0.0)) {
    f.summary.fail("akf: R_N2 = " + number(R) + ": must be finite and > 0");
    return f;
  }
  if (!model.Ad.allFinite() || !model.Bd.allFinite() || !model.C.allFinite()) {
    f.summary.fail("akf: the model has non-finite entries");
    return f;
  }
  const Index n = model.order(), m = n + 1;
  // 004 eqs 2.6-2.8 with Ad, Bd (E3) and D = 0 (E2).
  f.A_a = MatrixXd::Zero(m, m);
  f.A_a.topLeftCorner(n, n) = model.Ad;
  f.A_a.topRightCorner(n, 1) = model.Bd;
  f.A_a(n, n) = 1.0;
  f.G_a = Eigen::RowVectorXd::Zero(m);
  f.G_a.head(n) = model.C;
  MatrixXd Q = MatrixXd::Zero(m, m);
  Q(n, n) = S;  // Q0 = 0 (format)
  const MatrixXd Rm = MatrixXd::Constant(1, 1, R);
  const kalman::SteadyStateKalman ss = kalman::steady_state_gain(f.A_a, f.G_a, Q, Rm);
  f.dare_residual = ss.residual;
  f.spectral_radius = ss.spectral_radius;
  if (!ss.summary.ok()) {
    f.summary.fail("akf: the steady-state gain failed at S_N2 = " + number(S) + ": " +
                   ss.summary.message);
    return f;
  }
  f.K = ss.K.col(0);
  f.L = ss.L.col(0);
  f.Phi = f.A_a - f.L * f.G_a;
  // p(k+1|k+1) = e_F^T (z- + K (y - G_a z-)) = (e_F^T - K_F G_a) z- + K_F y.
  f.h = -f.K[n] * f.G_a;
  f.h[n] += 1.0;
  if (!modal_form(f, m)) {
    f.modal = false;
    f.pairs = 0;
    f.b = f.L;
    f.g = f.G_a;
  }
  f.summary.succeed();
  return f;
}

void run_akf(const AkfFilter& f, const Eigen::Ref<const VectorXd>& y, VectorXd* force) {
  if (!f.summary.ok()) throw std::invalid_argument("akf: run_akf needs a designed filter");
  const Index N = y.size();
  if (N < 2) throw std::invalid_argument("akf: y must hold at least 2 samples");
  force->resize(N);
  const double kF = f.K[f.K.size() - 1];
  double* out = force->data();
  // Contiguous copy only when y is strided (Ref may point into a matrix row).
  VectorXd copy;
  const double* yp = y.data();
  if (y.innerStride() != 1) {
    copy = y;
    yp = copy.data();
  }
  dispatch(
      f,
      [&](auto P, auto S1) {
        modal_pass<decltype(P)::value, decltype(S1)::value>(f, yp, N, out, kF);
      },
      [&](auto M) { dense_pass<decltype(M)::value>(f, yp, N, out, kF); });
  (*force)[N - 1] = (*force)[N - 2];  // format: the last sample repeated
}

double akf_error_norm(const AkfFilter& f, const Eigen::Ref<const VectorXd>& y, Index begin,
                      Index end, Index skip) {
  if (!f.summary.ok()) throw std::invalid_argument("akf: akf_error_norm needs a designed filter");
  if (begin < 0 || skip < 0 || begin + skip >= end || end > y.size()) {
    throw std::invalid_argument(
        "akf: the error-norm window needs 0 <= begin, begin + skip < end "
        "<= y.size() (begin " +
        std::to_string(begin) + ", skip " + std::to_string(skip) + ", end " + std::to_string(end) +
        ", size " + std::to_string(y.size()) + ")");
  }
  VectorXd copy;
  const double* yp = y.data();
  if (y.innerStride() != 1) {
    copy = y;
    yp = copy.data();
  }
  const Index from = begin + skip;
  return dispatch(
      f,
      [&](auto P, auto S1) {
        return modal_error<decltype(P)::value, decltype(S1)::value>(f, yp, begin, from, end);
      },
      [&](auto M) { return dense_error<decltype(M)::value>(f, yp, begin, from, end); });
}

Index akf_knee_index(const Eigen::Ref<const VectorXd>& E, double knee_tol, double dip_tol) {
  Index argmin = -1, last = -1;
  for (Index i = 0; i < E.size(); ++i) {
    if (!std::isfinite(E[i])) continue;
    if (argmin < 0 || E[i] < E[argmin]) argmin = i;
    last = i;
  }
  if (argmin < 0) return -1;
  const double m = E[argmin];
  if (E[last] > (1.0 + dip_tol) * m) return argmin;  // E dips: the S of the minimum
  for (Index i = 0; i < E.size(); ++i) {
    if (std::isfinite(E[i]) && E[i] <= (1.0 + knee_tol) * m) return i;
  }
  return argmin;  // not reached: E[argmin] qualifies
}

VectorXd akf_S_grid(const AkfOptions& o) {
  validate(o);
  // Count with a 1e-9 decade margin so that 1e-5..1e5 holds both ends despite rounding.
  const double decades = std::log10(o.S_max_N2 / o.S_min_N2);
  const Index count = static_cast<Index>(std::floor(decades * o.S_per_decade + 1e-9)) + 1;
  VectorXd S(count);
  for (Index i = 0; i < count; ++i) {
    S[i] = o.S_min_N2 * std::pow(10.0, static_cast<double>(i) / o.S_per_decade);
  }
  return S;
}

SampleWindow akf_tuning_window(Index samples, double fs, double c0, double c1,
                               const AkfOptions& o) {
  validate(o);
  require_rule(std::isfinite(fs) && fs > 0.0, "sample_rate_hz", fs, "must be finite and > 0");
  require_rule(std::isfinite(c0) && std::isfinite(c1) && c0 >= 0.0 && c1 > c0, "cut_window_s",
               "[" + number(c0) + ", " + number(c1) + "]", "must be finite with 0 <= c0 < c1");
  SampleWindow w;
  w.begin = std::min<Index>(samples, static_cast<Index>(std::ceil(c0 * fs)));
  const Index length = static_cast<Index>(std::llround((o.skip_s + o.tuning_length_s) * fs));
  const Index cut_end = static_cast<Index>(std::floor(c1 * fs));
  w.end = std::min({samples, cut_end, w.begin + length});
  w.end = std::max(w.end, w.begin);
  return w;
}

AkfResult reconstruct_force_akf(const DiscreteModel& model, const Eigen::Ref<const VectorXd>& y,
                                double R, const SampleWindow& window, const AkfOptions& options) {
  validate(options);
  AkfResult r;
  r.S_from_knee = true;
  if (window.begin < 0 || window.end > y.size() || window.begin > window.end) {
    throw std::invalid_argument("akf: the tuning window [" + std::to_string(window.begin) + ", " +
                                std::to_string(window.end) + ") must lie in the record of " +
                                std::to_string(y.size()) + " samples");
  }
  if (!check_data(model, y, R, r)) return r;
  r.tuning_window = window;
  r.tuning_skip = static_cast<Index>(std::llround(options.skip_s * model.sample_rate_hz));
  if (window.end - window.begin <= r.tuning_skip) {
    r.summary.fail("akf: the tuning window [" + std::to_string(window.begin) + ", " +
                   std::to_string(window.end) + ") holds no sample after the " +
                   std::to_string(r.tuning_skip) +
                   " skipped (akf.skip_s = " + number(options.skip_s) + ")");
    return r;
  }
  r.S_grid_N2 = akf_S_grid(options);
  const Index count = r.S_grid_N2.size();
  r.E = VectorXd::Constant(count, std::numeric_limits<double>::quiet_NaN());
  std::vector<AkfFilter> filters(static_cast<std::size_t>(count));
  int failed = 0;
  std::string first_failure;
  for (Index i = 0; i < count; ++i) {
    AkfFilter& f = filters[static_cast<std::size_t>(i)];
    f = design_akf(model, r.S_grid_N2[i], R);
    if (!f.summary.ok()) {
      if (failed++ == 0) first_failure = f.summary.message;
      continue;
    }
    r.E[i] = akf_error_norm(f, y, window.begin, window.end, r.tuning_skip);
  }
  r.knee_index = akf_knee_index(r.E, options.knee_tolerance, options.dip_tolerance);
  if (r.knee_index < 0) {
    r.summary.fail("akf: no S of the grid gave a filter: " + first_failure);
    return r;
  }
  if (failed > 0) {
    r.summary.warnings.push_back(
        "akf: " + std::to_string(failed) + " of " + std::to_string(count) +
        " grid values of S gave no filter (E is NaN there): " + first_failure);
  }
  if (r.knee_index == count - 1) {
    r.summary.warnings.push_back(
        "akf: the knee of E(S) is at the grid's largest S: E was still falling there");
  }
  finish(filters[static_cast<std::size_t>(r.knee_index)], y, r);
  return r;
}

AkfResult reconstruct_force_akf_fixed_S(const DiscreteModel& model,
                                        const Eigen::Ref<const VectorXd>& y, double R, double S) {
  AkfResult r;
  if (!check_data(model, y, R, r)) return r;
  const AkfFilter f = design_akf(model, S, R);
  if (!f.summary.ok()) {
    r.S_N2 = S;
    r.summary.fail(f.summary.message);
    return r;
  }
  finish(f, y, r);
  return r;
}

}  // namespace forcerec
}  // namespace chatterlab
