#include "analysis/forcerec/transfer_fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "analysis/common/ceres_lm.h"
#include "analysis/common/check.h"
#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/common/require.h"
#include "analysis/metrics/metrics.h"

namespace chatterlab {
namespace forcerec {
namespace {

using cd = std::complex<double>;

// Two roots are conjugates, and two poles distinct, within this x |s| (eigenvalues of a real
// matrix come in exactly conjugate pairs; roots typed by hand or rounded in a table do not).
constexpr double kConjugateTolerance = 1e-9;
constexpr double kDistinctPoleTolerance = 1e-9;
// Vector fitting: the bounds of |d~| of the relaxed sigma (vectfit3's TOLlow, TOLhigh): outside,
// d~ is fixed at the bound and the non-relaxed problem solved (Gustavsen 2006, sec. IV).
constexpr double kSigmaDLow = 1e-8;
constexpr double kSigmaDHigh = 1e8;
// Starting poles: -w / 100 +- j w (Gustavsen & Semlyen 1999, sec. 5: light damping).
constexpr double kStartDampingRatio = 0.01;
// The relative degree is above one when |C B| < this x |C| |B| in the scaled coordinates.
constexpr double kRelativeDegreeTolerance = 1e-12;
// Floors of the log parametrization of step 3 (scaled units): a root on the imaginary axis or at
// the origin starts just inside the left half plane.
constexpr double kLogFloor = 1e-9;

std::string num_text(double v) { return significant_text(v, 6); }

RootPair make_root_pair(cd s) {
  RootPair p;
  p.s = s.imag() < 0.0 ? std::conj(s) : s;
  const double r = std::abs(p.s);
  p.fn_hz = r / kTwoPi;
  p.zeta = r > 0.0 ? -p.s.real() / r : 0.0;
  return p;
}

struct SplitRoots {
  std::vector<RootPair> pairs;
  std::vector<double> reals;
};

// Complex roots (|Im s| > kConjugateTolerance |s|) matched into conjugate pairs; the others are
// real (their imaginary part dropped).
SplitRoots split_roots(const Eigen::Ref<const Eigen::VectorXcd>& roots, const std::string& field) {
  SplitRoots out;
  std::vector<cd> upper, lower;
  for (Eigen::Index i = 0; i < roots.size(); ++i) {
    const cd s = roots[i];
    require_rule(std::isfinite(s.real()) && std::isfinite(s.imag()),
                 field + "[" + std::to_string(i) + "]", s, "must be finite");
    if (std::abs(s.imag()) <= kConjugateTolerance * std::abs(s)) {
      out.reals.push_back(s.real());
    } else if (s.imag() > 0.0) {
      upper.push_back(s);
    } else {
      lower.push_back(s);
    }
  }
  std::vector<bool> used(lower.size(), false);
  for (const cd& u : upper) {
    bool found = false;
    for (std::size_t k = 0; k < lower.size() && !found; ++k) {
      if (!used[k] && std::abs(lower[k] - std::conj(u)) <= kConjugateTolerance * std::abs(u)) {
        used[k] = true;
        found = true;
      }
    }
    require_rule(found, field + " root", u, "has no conjugate partner (a real polynomial's roots)");
    out.pairs.push_back(make_root_pair(u));
  }
  for (std::size_t k = 0; k < lower.size(); ++k)
    require_rule(bool(used[k]), field + " root", lower[k],
                 "has no conjugate partner (a real polynomial's roots)");
  std::sort(out.pairs.begin(), out.pairs.end(),
            [](const RootPair& a, const RootPair& b) { return a.fn_hz < b.fn_hz; });
  std::sort(out.reals.begin(), out.reals.end(),
            [](double a, double b) { return std::abs(a) < std::abs(b); });
  return out;
}

Eigen::VectorXcd expand(const std::vector<RootPair>& pairs, const std::vector<double>& reals) {
  Eigen::VectorXcd r(static_cast<Eigen::Index>(2 * pairs.size() + reals.size()));
  Eigen::Index k = 0;
  for (const RootPair& p : pairs) {
    r[k++] = p.s;
    r[k++] = std::conj(p.s);
  }
  for (double x : reals) r[k++] = cd(x, 0.0);
  return r;
}

// Roots of the monic s^m + c1 s^(m-1) + ... + cm: eigenvalues of the companion matrix of the
// polynomial in s~ = s / w0, w0 = max_i |c_i|^(1/i) (a bound of the order of the largest root),
// so that the scaled coefficients are O(1) and not 1e3..1e24 as in 004 Table 3.1.
Eigen::VectorXcd monic_roots(const Eigen::Ref<const Eigen::VectorXd>& c) {
  const Eigen::Index m = c.size();
  if (m == 0) return Eigen::VectorXcd();
  double w0 = 0.0;
  for (Eigen::Index i = 0; i < m; ++i)
    w0 = std::max(w0, std::pow(std::abs(c[i]), 1.0 / static_cast<double>(i + 1)));
  if (!(w0 > 0.0)) w0 = 1.0;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    companion(0, i) = -c[i] / std::pow(w0, static_cast<double>(i + 1));
  if (m > 1) companion.bottomLeftCorner(m - 1, m - 1).setIdentity();
  Eigen::EigenSolver<Eigen::MatrixXd> es(companion, false);
  CHATTERLAB_CHECK(es.info() == Eigen::Success, "companion eigenvalues did not converge");
  return es.eigenvalues() * w0;
}

// [1, c1 .. cm] of prod (s - r) over the roots, pairs as real quadratics.
Eigen::VectorXd monic_polynomial(const std::vector<RootPair>& pairs,
                                 const std::vector<double>& reals) {
  Eigen::VectorXd p = Eigen::VectorXd::Ones(1);
  auto times = [&p](const Eigen::VectorXd& f) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(p.size() + f.size() - 1);
    for (Eigen::Index i = 0; i < p.size(); ++i)
      for (Eigen::Index j = 0; j < f.size(); ++j) q[i + j] += p[i] * f[j];
    p = q;
  };
  for (const RootPair& r : pairs) times(Eigen::Vector3d(1.0, -2.0 * r.s.real(), std::norm(r.s)));
  for (double x : reals) times(Eigen::Vector2d(1.0, -x));
  return p;
}

// ---------------------------------------------------------------------------------------------
// Step 1: vector fitting in the scaled variable s~ (one complex pole per pair, Im > 0, or a
// real pole with Im = 0).
using PoleSet = std::vector<cd>;

Eigen::Index basis_size(const PoleSet& a) {
  Eigen::Index n = 0;
  for (const cd& p : a) n += p.imag() > 0.0 ? 2 : 1;
  return n;
}

// The real-coefficient basis (Gustavsen & Semlyen 1999, appendix): a real pole gives
// 1 / (s - a); a pair gives 1/(s - a) + 1/(s - conj a) and j/(s - a) - j/(s - conj a), whose
// real coefficients c', c'' are the residue c' + j c'' at a.
Eigen::RowVectorXcd basis_row(cd s, const PoleSet& a) {
  Eigen::RowVectorXcd row(basis_size(a));
  Eigen::Index k = 0;
  for (const cd& p : a) {
    if (p.imag() > 0.0) {
      const cd u = 1.0 / (s - p), v = 1.0 / (s - std::conj(p));
      row[k++] = u + v;
      row[k++] = cd(0.0, 1.0) * (u - v);
    } else {
      row[k++] = 1.0 / (s - p);
    }
  }
  return row;
}

// The realization (Lambda, b) with c (sI - Lambda)^-1 b = c . basis_row(s): pair blocks
// [[a', a''], [-a'', a']] with b = [2, 0], real poles a with b = 1.
void pole_realization(const PoleSet& a, Eigen::MatrixXd* L, Eigen::VectorXd* b) {
  const Eigen::Index n = basis_size(a);
  L->setZero(n, n);
  b->setZero(n);
  Eigen::Index k = 0;
  for (const cd& p : a) {
    if (p.imag() > 0.0) {
      (*L)(k, k) = p.real();
      (*L)(k, k + 1) = p.imag();
      (*L)(k + 1, k) = -p.imag();
      (*L)(k + 1, k + 1) = p.real();
      (*b)[k] = 2.0;
      k += 2;
    } else {
      (*L)(k, k) = p.real();
      (*b)[k] = 1.0;
      k += 1;
    }
  }
}

// Least squares with the columns scaled to unit norm (as vectfit3), by column-pivoting QR.
Eigen::VectorXd scaled_least_squares(Eigen::MatrixXd M, const Eigen::VectorXd& rhs) {
  Eigen::VectorXd scale(M.cols());
  for (Eigen::Index j = 0; j < M.cols(); ++j) {
    const double norm = M.col(j).norm();
    scale[j] = norm > 0.0 ? 1.0 / norm : 1.0;
    M.col(j) *= scale[j];
  }
  return M.colPivHouseholderQr().solve(rhs).cwiseProduct(scale);
}

// The eigenvalues of a real matrix as a PoleSet, unstable ones flipped into the left half
// plane (their count added to *flipped), sorted by |a|.
PoleSet poles_from_eigenvalues(const Eigen::VectorXcd& ev, int* flipped) {
  PoleSet a;
  for (Eigen::Index i = 0; i < ev.size(); ++i) {
    cd p = ev[i];
    if (p.imag() < 0.0) continue;  // the partner of a pair with Im > 0
    if (p.real() > 0.0) {
      p = cd(-p.real(), p.imag());
      *flipped += p.imag() > 0.0 ? 2 : 1;
    }
    a.push_back(p);
  }
  std::sort(a.begin(), a.end(), [](const cd& x, const cd& y) { return std::abs(x) < std::abs(y); });
  return a;
}

struct BandData {
  Eigen::VectorXcd s;  // j w / w_ref
  Eigen::VectorXcd H;
  Eigen::VectorXd weight;
};

// One pole relocation with the relaxed sigma (Gustavsen 2006): unknowns c (G's residues),
// c~ and d~ (sigma = d~ + sum c~ phi); rows w_i (c phi - H c~ phi - H d~) = 0, and
// Re sum_i sigma(s_i) = N as the relaxation's normalization row (weighted as vectfit3). The
// new poles are the zeros of sigma, eig(Lambda - b c~ / d~).
PoleSet relocate_poles(const BandData& d, const PoleSet& a, int* flipped) {
  const Eigen::Index N = d.s.size();
  const Eigen::Index n = basis_size(a);
  Eigen::MatrixXcd phi(N, n);
  for (Eigen::Index i = 0; i < N; ++i) phi.row(i) = basis_row(d.s[i], a);

  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * N + 1, 2 * n + 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * N + 1);
  for (Eigen::Index i = 0; i < N; ++i) {
    const double w = d.weight[i];
    const Eigen::RowVectorXcd g = w * phi.row(i);
    const Eigen::RowVectorXcd sg = -w * d.H[i] * phi.row(i);
    const cd sd = -w * d.H[i];
    M.block(2 * i, 0, 1, n) = g.real();
    M.block(2 * i + 1, 0, 1, n) = g.imag();
    M.block(2 * i, n, 1, n) = sg.real();
    M.block(2 * i + 1, n, 1, n) = sg.imag();
    M(2 * i, 2 * n) = sd.real();
    M(2 * i + 1, 2 * n) = sd.imag();
  }
  const double Nd = static_cast<double>(N);
  const double scale = (d.weight.cwiseProduct(d.H.cwiseAbs())).norm() / Nd;
  M.block(2 * N, n, 1, n) = phi.colwise().sum().real() * scale;
  M(2 * N, 2 * n) = Nd * scale;
  rhs[2 * N] = Nd * scale;
  Eigen::VectorXd x = scaled_least_squares(M, rhs);
  Eigen::VectorXd c_sigma = x.segment(n, n);
  double d_sigma = x[2 * n];

  if (!(std::abs(d_sigma) >= kSigmaDLow && std::abs(d_sigma) <= kSigmaDHigh)) {
    // d~ fixed at the bound: the non-relaxed problem with the sigma constant on the right.
    const double sign = d_sigma < 0.0 ? -1.0 : 1.0;
    d_sigma = sign * std::clamp(std::abs(d_sigma), kSigmaDLow, kSigmaDHigh);
    Eigen::MatrixXd M2 = M.topLeftCorner(2 * N, 2 * n);
    Eigen::VectorXd rhs2(2 * N);
    for (Eigen::Index i = 0; i < N; ++i) {
      const cd r = d.weight[i] * d.H[i] * d_sigma;
      rhs2[2 * i] = r.real();
      rhs2[2 * i + 1] = r.imag();
    }
    c_sigma = scaled_least_squares(M2, rhs2).segment(n, n);
  }
  Eigen::MatrixXd L;
  Eigen::VectorXd b;
  pole_realization(a, &L, &b);
  const Eigen::MatrixXd Z = L - b * c_sigma.transpose() / d_sigma;
  Eigen::EigenSolver<Eigen::MatrixXd> es(Z, false);
  CHATTERLAB_CHECK(es.info() == Eigen::Success, "eigenvalues of the relocated poles");
  PoleSet next = poles_from_eigenvalues(es.eigenvalues(), flipped);
  CHATTERLAB_CHECK(basis_size(next) == n, "relocation kept the number of poles");
  return next;
}

// The residues (real coefficients of basis_row) for fixed poles.
Eigen::VectorXd fit_residues(const BandData& d, const PoleSet& a) {
  const Eigen::Index N = d.s.size();
  const Eigen::Index n = basis_size(a);
  Eigen::MatrixXd M(2 * N, n);
  Eigen::VectorXd rhs(2 * N);
  for (Eigen::Index i = 0; i < N; ++i) {
    const Eigen::RowVectorXcd g = d.weight[i] * basis_row(d.s[i], a);
    M.row(2 * i) = g.real();
    M.row(2 * i + 1) = g.imag();
    rhs[2 * i] = d.weight[i] * d.H[i].real();
    rhs[2 * i + 1] = d.weight[i] * d.H[i].imag();
  }
  return scaled_least_squares(M, rhs);
}

bool same_structure_and_close(const PoleSet& a, const PoleSet& b, double tol) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if ((a[k].imag() > 0.0) != (b[k].imag() > 0.0)) return false;
    if (std::abs(a[k] - b[k]) > tol * std::abs(a[k])) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Step 3: the factored form on the log parametrization (scaled units). Parameters:
// [k, (ln wn, ln zeta) per pole pair, ln(-p) per real pole, the same for the zeros].
struct Structure {
  int pole_pairs = 0;
  int real_poles = 0;
  int zero_pairs = 0;
  int real_zeros = 0;
  int parameters() const { return 1 + 2 * pole_pairs + real_poles + 2 * zero_pairs + real_zeros; }
};

struct FactoredResidual {
  const Eigen::VectorXd* w;  // w_i / w_ref
  const Eigen::VectorXcd* H;
  const Eigen::VectorXd* weight;  // w_i / (rms of w H)
  Structure st;

  template <typename T>
  static void times(T* re, T* im, const T& qr, const T& qi) {
    const T r = *re * qr - *im * qi;
    *im = *re * qi + *im * qr;
    *re = r;
  }

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    using std::exp;
    const T* t = parameters[0];
    for (Eigen::Index i = 0; i < w->size(); ++i) {
      const double wi = (*w)[i];
      T dr(1.0), di(0.0), nr(1.0), ni(0.0);
      int k = 1;
      auto quadratic = [&](T* re, T* im) {
        const T wn = exp(t[k]), zeta = exp(t[k + 1]);
        times(re, im, T(wn * wn - wi * wi), T(2.0 * wi) * zeta * wn);
        k += 2;
      };
      auto linear = [&](T* re, T* im) {
        times(re, im, T(exp(t[k])), T(wi));
        k += 1;
      };
      for (int j = 0; j < st.pole_pairs; ++j) quadratic(&dr, &di);
      for (int j = 0; j < st.real_poles; ++j) linear(&dr, &di);
      for (int j = 0; j < st.zero_pairs; ++j) quadratic(&nr, &ni);
      for (int j = 0; j < st.real_zeros; ++j) linear(&nr, &ni);
      const T den = dr * dr + di * di;
      const T gr = t[0] * (nr * dr + ni * di) / den;
      const T gi = t[0] * (ni * dr - nr * di) / den;
      residuals[2 * i] = (*weight)[i] * (gr - (*H)[i].real());
      residuals[2 * i + 1] = (*weight)[i] * (gi - (*H)[i].imag());
    }
    return true;
  }
};

// The parameters of a (minimum-phase, stable) model in scaled units.
std::vector<double> to_parameters(const TransferModel& m, double w_ref, double k) {
  std::vector<double> t{k};
  auto pair = [&t, w_ref](const RootPair& p) {
    t.push_back(std::log(std::max(std::abs(p.s) / w_ref, kLogFloor)));
    t.push_back(std::log(std::max(p.zeta, kLogFloor)));
  };
  auto real = [&t, w_ref](double x) { t.push_back(std::log(std::max(-x / w_ref, kLogFloor))); };
  for (const RootPair& p : m.pole_pairs) pair(p);
  for (double x : m.real_poles_rad_s) real(x);
  for (const RootPair& p : m.zero_pairs) pair(p);
  for (double x : m.real_zeros_rad_s) real(x);
  return t;
}

// The roots of the factors: a quadratic with zeta >= 1 gives two real roots.
TransferModel from_parameters(const std::vector<double>& t, const Structure& st, double w_ref) {
  std::vector<cd> poles, zeros;
  std::size_t k = 1;
  auto quadratic = [&](std::vector<cd>* roots) {
    const double wn = std::exp(t[k]) * w_ref, zeta = std::exp(t[k + 1]);
    k += 2;
    if (zeta < 1.0) {
      const cd s(-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta));
      roots->push_back(s);
      roots->push_back(std::conj(s));
    } else {
      const double d = std::sqrt(zeta * zeta - 1.0);
      roots->push_back(cd(-wn * (zeta - d), 0.0));
      roots->push_back(cd(-wn * (zeta + d), 0.0));
    }
  };
  auto linear = [&](std::vector<cd>* roots) {
    roots->push_back(cd(-std::exp(t[k++]) * w_ref, 0.0));
  };
  for (int j = 0; j < st.pole_pairs; ++j) quadratic(&poles);
  for (int j = 0; j < st.real_poles; ++j) linear(&poles);
  for (int j = 0; j < st.zero_pairs; ++j) quadratic(&zeros);
  for (int j = 0; j < st.real_zeros; ++j) linear(&zeros);
  return transfer_model_from_roots(
      Eigen::Map<const Eigen::VectorXcd>(poles.data(), static_cast<Eigen::Index>(poles.size())),
      Eigen::Map<const Eigen::VectorXcd>(zeros.data(), static_cast<Eigen::Index>(zeros.size())),
      t[0] * w_ref);
}

std::string roots_text(const std::vector<RootPair>& pairs, const std::vector<double>& reals) {
  std::string s;
  for (const RootPair& p : pairs)
    s += "\n    fn = " + num_text(p.fn_hz) + " Hz, zeta = " + significant_text(p.zeta, 4);
  for (double x : reals) s += "\n    real " + num_text(x) + " rad/s";
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
int TransferModel::order() const {
  return static_cast<int>(2 * pole_pairs.size() + real_poles_rad_s.size());
}
Eigen::VectorXcd TransferModel::poles() const { return expand(pole_pairs, real_poles_rad_s); }
Eigen::VectorXcd TransferModel::zeros() const { return expand(zero_pairs, real_zeros_rad_s); }

TransferModel transfer_model_from_roots(const Eigen::Ref<const Eigen::VectorXcd>& poles,
                                        const Eigen::Ref<const Eigen::VectorXcd>& zeros,
                                        double b1) {
  require_rule(poles.size() >= 1, "poles.size()", poles.size(), "must be >= 1");
  require_rule(zeros.size() + 1 == poles.size(), "zeros.size()", zeros.size(),
               "must be poles.size() - 1 = " + std::to_string(poles.size() - 1) +
                   " (relative degree one, 004 eq. 3.1)");
  require_rule(std::isfinite(b1) && b1 != 0.0, "b1", b1, "must be finite and non-zero");
  SplitRoots p = split_roots(poles, "poles");
  SplitRoots z = split_roots(zeros, "zeros");
  TransferModel m;
  m.pole_pairs = std::move(p.pairs);
  m.real_poles_rad_s = std::move(p.reals);
  m.zero_pairs = std::move(z.pairs);
  m.real_zeros_rad_s = std::move(z.reals);
  m.b1 = b1;
  return m;
}

TransferModel transfer_model_from_coefficients(const Eigen::Ref<const Eigen::VectorXd>& num,
                                               const Eigen::Ref<const Eigen::VectorXd>& den) {
  const Eigen::Index n = den.size();
  require_rule(n >= 1, "den.size()", n, "must be >= 1 (004 eq. 3.1: [a1 .. an])");
  require_rule(num.size() == n, "num.size()", num.size(),
               "must equal den.size() = " + std::to_string(n) + " (004 eq. 3.1: [b1 .. bn])");
  for (Eigen::Index i = 0; i < n; ++i) {
    require_rule(std::isfinite(den[i]), "den[" + std::to_string(i) + "]", den[i], "must be finite");
    require_rule(std::isfinite(num[i]), "num[" + std::to_string(i) + "]", num[i], "must be finite");
  }
  require_rule(num[0] != 0.0, "num[0]", num[0], "must be non-zero (b1: relative degree one)");
  const Eigen::VectorXd monic_num = num.tail(n - 1) / num[0];
  return transfer_model_from_roots(monic_roots(den), monic_roots(monic_num), num[0]);
}

Eigen::VectorXd numerator_coefficients(const TransferModel& model) {
  return model.b1 * monic_polynomial(model.zero_pairs, model.real_zeros_rad_s);
}

Eigen::VectorXd denominator_coefficients(const TransferModel& model) {
  const Eigen::VectorXd p = monic_polynomial(model.pole_pairs, model.real_poles_rad_s);
  return p.tail(p.size() - 1);
}

double dc_gain(const TransferModel& model) {
  // b1 prod(-z) / prod(-p), as alternating ratios (no overflow at high orders).
  const Eigen::VectorXcd p = model.poles(), z = model.zeros();
  CHATTERLAB_CHECK(p.size() == z.size() + 1, "a model has one pole more than zeros");
  cd g = model.b1 / (-p[0]);
  for (Eigen::Index i = 0; i < z.size(); ++i) g *= (-z[i]) / (-p[i + 1]);
  return g.real();
}

std::complex<double> transfer_response(const TransferModel& model, double f_hz) {
  const Eigen::VectorXcd p = model.poles(), z = model.zeros();
  CHATTERLAB_CHECK(p.size() == z.size() + 1, "a model has one pole more than zeros");
  const cd s(0.0, kTwoPi * f_hz);
  cd g = model.b1 / (s - p[0]);
  for (Eigen::Index i = 0; i < z.size(); ++i) g *= (s - z[i]) / (s - p[i + 1]);
  return g;
}

Eigen::VectorXcd transfer_response(const TransferModel& model,
                                   const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  Eigen::VectorXcd g(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) g[i] = transfer_response(model, f_hz[i]);
  return g;
}

int rhp_zero_count(const TransferModel& model) {
  int count = 0;
  for (const RootPair& p : model.zero_pairs) count += p.s.real() > 0.0 ? 2 : 0;
  for (double x : model.real_zeros_rad_s) count += x > 0.0 ? 1 : 0;
  return count;
}

TransferModel mirror_rhp_zeros(const TransferModel& model) {
  TransferModel m = model;
  for (RootPair& p : m.zero_pairs) p = make_root_pair(cd(-std::abs(p.s.real()), p.s.imag()));
  for (double& x : m.real_zeros_rad_s) x = -std::abs(x);
  return m;
}

ContinuousModel realize_scaled_modal(const TransferModel& model) {
  const Eigen::VectorXcd p = model.poles(), z = model.zeros();
  const Eigen::Index n = p.size();
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index l = j + 1; l < n; ++l)
      require_rule(std::abs(p[j] - p[l]) > kDistinctPoleTolerance * std::abs(p[j]), "poles", p[j],
                   "coincides with another pole: no diagonal (modal) realization");
  // r_j = b1 prod_i (p_j - z_i) / prod_{l != j} (p_j - p_l), as alternating ratios.
  auto residue = [&](Eigen::Index j) {
    cd r = model.b1;
    Eigen::Index zi = 0;
    for (Eigen::Index l = 0; l < n; ++l) {
      if (l == j) continue;
      r /= p[j] - p[l];
      if (zi < z.size()) r *= p[j] - z[zi++];
    }
    return r;
  };
  ContinuousModel out;
  out.A = Eigen::MatrixXd::Zero(n, n);
  out.B = Eigen::VectorXd::Zero(n);
  out.C = Eigen::RowVectorXd::Zero(n);
  // model.poles() lists each pair as s, conj(s), then the real poles.
  Eigen::Index k = 0;
  for (std::size_t q = 0; q < model.pole_pairs.size(); ++q, k += 2) {
    const cd s = p[k];
    const cd r = residue(k);
    const double beta = std::abs(r) > 0.0 ? std::sqrt(2.0 * std::abs(r)) : 1.0;
    out.A(k, k) = s.real();
    out.A(k, k + 1) = s.imag();
    out.A(k + 1, k) = -s.imag();
    out.A(k + 1, k + 1) = s.real();
    out.B[k] = beta;
    out.C[k] = 2.0 * r.real() / beta;
    out.C[k + 1] = 2.0 * r.imag() / beta;
  }
  for (; k < n; ++k) {
    const double r = residue(k).real();
    const double beta = r != 0.0 ? std::sqrt(std::abs(r)) : 1.0;
    out.A(k, k) = p[k].real();
    out.B[k] = beta;
    out.C[k] = r / beta;
  }
  return out;
}

double condition_number(const Eigen::Ref<const Eigen::MatrixXd>& A) {
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  if (sv.size() == 0) return std::numeric_limits<double>::quiet_NaN();
  const double lo = sv[sv.size() - 1];
  return lo > 0.0 ? sv[0] / lo : std::numeric_limits<double>::infinity();
}

// ---------------------------------------------------------------------------------------------
TransferFit fit_transfer_function(const Eigen::Ref<const Eigen::VectorXd>& f_hz,
                                  const Eigen::Ref<const Eigen::VectorXcd>& H,
                                  const TransferFitOptions& o) {
  require_rule(H.size() == f_hz.size(), "H.size()", H.size(),
               "must equal f_hz.size() = " + std::to_string(f_hz.size()));
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    require_rule(std::isfinite(f_hz[i]) && f_hz[i] >= 0.0, "f_hz[" + std::to_string(i) + "]",
                 f_hz[i], "must be finite and >= 0");
    require_rule(std::isfinite(H[i].real()) && std::isfinite(H[i].imag()),
                 "H[" + std::to_string(i) + "]", H[i], "must be finite");
  }
  require_rule(o.order >= 2 && o.order % 2 == 0, "order", o.order,
               "must be even and >= 2 (004 eq. 3.1 with n/2 starting pole pairs)");
  require_rule(std::isnan(o.band_lo_hz) || (std::isfinite(o.band_lo_hz) && o.band_lo_hz >= 0.0),
               "band_lo_hz", o.band_lo_hz, "must be finite and >= 0, or NaN (the data's lowest)");
  require_rule(std::isnan(o.band_hi_hz) || std::isfinite(o.band_hi_hz), "band_hi_hz", o.band_hi_hz,
               "must be finite, or NaN (the data's highest)");
  if (!std::isnan(o.band_lo_hz) && !std::isnan(o.band_hi_hz))
    require_rule(o.band_hi_hz > o.band_lo_hz, "band_hi_hz", o.band_hi_hz,
                 "must be > band_lo_hz = " + num_text(o.band_lo_hz));
  require_rule(o.vf_max_iterations >= 1, "vf_max_iterations", o.vf_max_iterations, "must be >= 1");
  require_rule(o.vf_pole_tolerance > 0.0, "vf_pole_tolerance", o.vf_pole_tolerance, "must be > 0");
  require_rule(o.refine_max_iterations >= 0, "refine_max_iterations", o.refine_max_iterations,
               "must be >= 0");
  require_rule(o.min_zeta > 0.0 && o.min_zeta < 1.0, "min_zeta", o.min_zeta, "must be in (0, 1)");

  const double lo = std::isnan(o.band_lo_hz) ? -1.0 : o.band_lo_hz;
  const double hi =
      std::isnan(o.band_hi_hz) ? std::numeric_limits<double>::infinity() : o.band_hi_hz;
  std::vector<Eigen::Index> in_band;
  for (Eigen::Index i = 0; i < f_hz.size(); ++i)
    if (f_hz[i] >= lo && f_hz[i] <= hi) in_band.push_back(i);
  const auto N = static_cast<Eigen::Index>(in_band.size());
  const std::string band_text = "[" + num_text(std::isnan(o.band_lo_hz) ? 0.0 : lo) + ", " +
                                (std::isnan(o.band_hi_hz) ? std::string("max") : num_text(hi)) +
                                "] Hz";
  require_rule(N >= 2 * o.order, "points in the band " + band_text, N,
               "needs at least 2 order = " + std::to_string(2 * o.order));

  TransferFit fit;
  fit.f_hz.resize(N);
  fit.H.resize(N);
  for (Eigen::Index i = 0; i < N; ++i) {
    fit.f_hz[i] = f_hz[in_band[static_cast<std::size_t>(i)]];
    fit.H[i] = H[in_band[static_cast<std::size_t>(i)]];
  }
  fit.band_lo_hz = fit.f_hz.minCoeff();
  fit.band_hi_hz = fit.f_hz.maxCoeff();
  require_rule(fit.band_hi_hz > 0.0, "highest frequency in the band", fit.band_hi_hz,
               "must be > 0");
  require_rule((fit.H.array() - fit.H.mean()).matrix().norm() > 0.0, "H in the band " + band_text,
               "constant", "must vary (004 eq. 3.2 divides by ||H - mean H||)");

  // Scaled variable s~ = s / w_ref: the band maps into j [0, 1].
  const double w_ref = kTwoPi * fit.band_hi_hz;
  BandData d;
  d.s.resize(N);
  d.H = fit.H;
  d.weight = Eigen::VectorXd::Ones(N);
  Eigen::VectorXd w_scaled(N);
  for (Eigen::Index i = 0; i < N; ++i) {
    w_scaled[i] = fit.f_hz[i] / fit.band_hi_hz;
    d.s[i] = cd(0.0, w_scaled[i]);
    if (o.weighting == FitWeighting::kRelative) {
      require_rule(std::abs(fit.H[i]) > 0.0, "H[" + std::to_string(in_band[std::size_t(i)]) + "]",
                   fit.H[i], "must be non-zero with weighting kRelative (w = 1 / |H|)");
      d.weight[i] = 1.0 / std::abs(fit.H[i]);
    }
  }

  // Step 1: starting poles spread evenly over the band (interior points), damping ratio 1 %.
  const int pairs = o.order / 2;
  const double w_lo = fit.band_lo_hz / fit.band_hi_hz;
  PoleSet a;
  for (int k = 0; k < pairs; ++k) {
    const double w = w_lo + (1.0 - w_lo) * (k + 0.5) / pairs;
    a.push_back(cd(-kStartDampingRatio * w, w));
  }
  for (int it = 0; it < o.vf_max_iterations; ++it) {
    PoleSet next = relocate_poles(d, a, &fit.poles_flipped);
    ++fit.vf_iterations;
    const bool converged = same_structure_and_close(a, next, o.vf_pole_tolerance);
    a = std::move(next);
    if (converged) break;
  }
  const Eigen::VectorXd c = fit_residues(d, a);

  // Step 2: zeros from the zero dynamics of (Lambda, b, c) with C B != 0: on ker c, with the
  // input that holds y = 0 (u = -c Lambda x / (c b)), x' = P Lambda x, P = I - b c / (c b).
  Eigen::MatrixXd L;
  Eigen::VectorXd b;
  pole_realization(a, &L, &b);
  const Eigen::Index n = L.rows();
  const double cb = c.dot(b);
  if (!(std::abs(cb) > kRelativeDegreeTolerance * c.norm() * b.norm())) {
    fit.summary.fail("the vector fit in " + band_text + " has relative degree above one (b1 = " +
                     num_text(cb * w_ref) + "): 004 eq. 3.1 needs b1 != 0");
    return fit;
  }
  const Eigen::MatrixXd Nk = orthogonal_complement(c);  // spans ker c^T
  const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n) - b * c.transpose() / cb;
  Eigen::VectorXcd zeros_scaled(n - 1);
  if (n > 1) {
    Eigen::EigenSolver<Eigen::MatrixXd> es(Nk.transpose() * P * L * Nk, false);
    if (es.info() != Eigen::Success) {
      fit.summary.fail("the zeros of the vector fit in " + band_text + " did not converge");
      return fit;
    }
    zeros_scaled = es.eigenvalues();
  }
  Eigen::VectorXcd poles_scaled(n);
  {
    Eigen::Index k = 0;
    for (const cd& p : a) {
      poles_scaled[k++] = p;
      if (p.imag() > 0.0) poles_scaled[k++] = std::conj(p);
    }
  }
  TransferModel vf_model;
  try {
    vf_model = transfer_model_from_roots(poles_scaled * w_ref, zeros_scaled * w_ref, cb * w_ref);
  } catch (const InputError& e) {
    fit.summary.fail(std::string("the vector fit's roots: ") + e.what());
    return fit;
  }
  fit.vf_fit_pct = metrics::nrmse_fit_pct(fit.H, transfer_response(vf_model, fit.f_hz));

  fit.zeros_mirrored = rhp_zero_count(vf_model);
  TransferModel model = mirror_rhp_zeros(vf_model);
  // The real gain refitted by linear least squares after the mirroring (the phase changed).
  {
    const double b1 = model.b1;
    model.b1 = 1.0;
    const Eigen::VectorXcd g0 = transfer_response(model, fit.f_hz);
    double num = 0.0, den = 0.0;
    for (Eigen::Index i = 0; i < N; ++i) {
      const double w2 = d.weight[i] * d.weight[i];
      num += w2 * (std::conj(g0[i]) * fit.H[i]).real();
      den += w2 * std::norm(g0[i]);
    }
    model.b1 = den > 0.0 && num != 0.0 ? num / den : b1;
  }

  // Step 3: Levenberg-Marquardt on the stable, minimum-phase parametrization.
  if (o.refine_max_iterations > 0) {
    Structure st;
    st.pole_pairs = static_cast<int>(model.pole_pairs.size());
    st.real_poles = static_cast<int>(model.real_poles_rad_s.size());
    st.zero_pairs = static_cast<int>(model.zero_pairs.size());
    st.real_zeros = static_cast<int>(model.real_zeros_rad_s.size());
    std::vector<double> theta = to_parameters(model, w_ref, model.b1 / w_ref);
    // The damping floor: pair k's ln zeta is parameter 2 + 2 k (poles), and after the real
    // poles for the zeros; a start below the floor moves onto it.
    std::vector<int> zeta_index;
    for (int j = 0; j < st.pole_pairs; ++j) zeta_index.push_back(2 + 2 * j);
    for (int j = 0; j < st.zero_pairs; ++j)
      zeta_index.push_back(1 + 2 * st.pole_pairs + st.real_poles + 2 * j + 1);
    const double log_min_zeta = std::log(o.min_zeta);
    for (int i : zeta_index) theta[std::size_t(i)] = std::max(theta[std::size_t(i)], log_min_zeta);
    // Residuals scaled by the rms of w H, so that the cost and its tolerances are O(1).
    const double rms =
        std::sqrt(d.weight.cwiseProduct(d.H.cwiseAbs()).squaredNorm() / static_cast<double>(N));
    const Eigen::VectorXd weight = d.weight / rms;
    auto* functor = new FactoredResidual{&w_scaled, &fit.H, &weight, st};
    auto* cost = new ceres::DynamicAutoDiffCostFunction<FactoredResidual, 4>(functor);
    cost->AddParameterBlock(st.parameters());
    cost->SetNumResiduals(static_cast<int>(2 * N));
    ceres::Problem problem;
    problem.AddResidualBlock(cost, nullptr, theta.data());
    for (int i : zeta_index) problem.SetParameterLowerBound(theta.data(), i, log_min_zeta);
    const ceres::Solver::Options options =
        dense_lm_options(o.refine_max_iterations, 1e-14, 1e-14, 1e-16);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    fit.refine_iterations = lm_iterations(summary);
    if (summary.termination_type == ceres::CONVERGENCE ||
        summary.termination_type == ceres::NO_CONVERGENCE) {
      try {
        model = from_parameters(theta, st, w_ref);
      } catch (const InputError& e) {
        fit.summary.warnings.push_back(std::string("the refined model was rejected (") + e.what() +
                                       "); the vector-fitting model is kept");
      }
      if (summary.termination_type == ceres::NO_CONVERGENCE)
        fit.summary.warnings.push_back("the refinement stopped after " +
                                       std::to_string(o.refine_max_iterations) +
                                       " iterations without converging: " + summary.message);
    } else {
      fit.summary.warnings.push_back("the refinement failed (" + summary.message +
                                     "); the vector-fitting model is kept");
    }
  }

  fit.model = model;
  fit.num = numerator_coefficients(model);
  fit.den = denominator_coefficients(model);
  fit.dc_gain = dc_gain(model);
  fit.G = transfer_response(model, fit.f_hz);
  fit.fit_pct = metrics::nrmse_fit_pct(fit.H, fit.G);
  try {
    fit.realization = realize_scaled_modal(model);
  } catch (const InputError& e) {
    fit.summary.fail(std::string("no modal realization of the fitted model: ") + e.what());
    return fit;
  }
  fit.realization_cond_A = condition_number(fit.realization.A);
  CHATTERLAB_CHECK(rhp_zero_count(fit.model) == 0, "the fitted model is minimum phase");

  if (fit.zeros_mirrored > 0)
    fit.summary.warnings.push_back(
        std::to_string(fit.zeros_mirrored) +
        " right-half-plane zero(s) of the vector fit mirrored into the left half plane (the "
        "sliding-mode observer needs a minimum-phase model): the model's phase departs from "
        "the data there");
  // On the floor within rounding (the bound is on ln zeta).
  constexpr double kOnFloor = 1.0 + 1e-6;
  for (const RootPair& p : fit.model.zero_pairs)
    if (p.zeta <= o.min_zeta * kOnFloor)
      fit.summary.warnings.push_back(
          "zero pair at " + num_text(p.fn_hz) + " Hz ended on the damping floor min_zeta = " +
          num_text(o.min_zeta) + ": the data want it on or beyond the imaginary axis");
  for (const RootPair& p : fit.model.pole_pairs)
    if (p.zeta <= o.min_zeta * kOnFloor)
      fit.summary.warnings.push_back(
          "pole pair at " + num_text(p.fn_hz) +
          " Hz ended on the damping floor min_zeta = " + num_text(o.min_zeta));
  for (const RootPair& p : fit.model.pole_pairs)
    if (p.fn_hz < fit.band_lo_hz || p.fn_hz > fit.band_hi_hz)
      fit.summary.warnings.push_back("pole pair at " + num_text(p.fn_hz) +
                                     " Hz lies outside the band " + band_text +
                                     ": the data do not support it");
  fit.summary.succeed();
  fit.summary.details =
      "order " + std::to_string(o.order) + " in [" + num_text(fit.band_lo_hz) + ", " +
      num_text(fit.band_hi_hz) + "] Hz (" + std::to_string(N) + " points): fit " +
      significant_text(fit.fit_pct, 4) + " % (004 eq. 3.2; vector fitting " +
      significant_text(fit.vf_fit_pct, 4) + " % after " + std::to_string(fit.vf_iterations) +
      " iterations), DC gain " + num_text(fit.dc_gain) + ", b1 " + num_text(fit.model.b1) +
      " 1/s\n  poles:" + roots_text(fit.model.pole_pairs, fit.model.real_poles_rad_s) +
      "\n  zeros:" + roots_text(fit.model.zero_pairs, fit.model.real_zeros_rad_s);
  return fit;
}

}  // namespace forcerec
}  // namespace chatterlab
