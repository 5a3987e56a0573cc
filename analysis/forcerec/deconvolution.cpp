#include "analysis/forcerec/deconvolution.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <deque>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "analysis/common/require.h"
#include "analysis/signal/fft.h"

namespace chatterlab {
namespace forcerec {

const char* to_string(AlphaRule rule) {
  switch (rule) {
    case AlphaRule::kDiscrepancy:
      return "discrepancy";
    case AlphaRule::kGcv:
      return "gcv";
    case AlphaRule::kLcurve:
      return "lcurve";
    case AlphaRule::kFixed:
      return "fixed";
  }
  return "?";
}

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXcd;
using Eigen::VectorXd;
using cplx = std::complex<double>;

// FFTW's fast lengths: products of 2, 3, 5 and 7.
bool seven_smooth(Index n) {
  for (Index p : {2, 3, 5, 7}) {
    while (n % p == 0) n /= p;
  }
  return n == 1;
}
// The largest even 7-smooth length <= n (FFTW's real transforms of odd lengths run ~3 times
// slower: 382,725 = 3^7 5^2 7 against 381,024 = 2^5 3^5 7^2); 1 when n < 2.
Index even_smooth_at_most(Index n) {
  if (n < 2) return 1;
  n -= n % 2;
  while (!seven_smooth(n)) n -= 2;
  return n;
}
Index smooth_at_least(Index n) {
  while (!seven_smooth(n)) ++n;
  return n;
}

// Parseval weights of the bins 0..P/2 of a real length-P signal: sum x^2 = (1/P) sum w |X|^2.
Eigen::ArrayXd half_spectrum_weights(Index P) {
  Eigen::ArrayXd w = Eigen::ArrayXd::Constant(P / 2 + 1, 2.0);
  w[0] = 1.0;
  if (P % 2 == 0) w[P / 2] = 1.0;
  return w;
}

// (G f)_i = C x(i+1) from rest, i = 0..M-1 (the rows y(1..M)).
VectorXd apply_toeplitz(const DiscreteModel& m, const VectorXd& f) {
  const Index n = m.order();
  VectorXd out(f.size());
  VectorXd x = VectorXd::Zero(n), xn(n);
  for (Index k = 0; k < f.size(); ++k) {
    xn.noalias() = m.Ad * x;
    xn += m.Bd * f[k];
    x.swap(xn);
    out[k] = m.C.dot(x);
  }
  return out;
}

// (G^T r)_j = Bd^T mu_j,  mu_j = C^T r_j + Ad^T mu_(j+1),  mu_M = 0.
VectorXd apply_toeplitz_transpose(const DiscreteModel& m, const VectorXd& r) {
  const Index n = m.order();
  const MatrixXd At = m.Ad.transpose();
  const VectorXd Ct = m.C.transpose();
  VectorXd out(r.size());
  VectorXd mu = VectorXd::Zero(n), mn(n);
  for (Index j = r.size() - 1; j >= 0; --j) {
    mn.noalias() = At * mu;
    mn += Ct * r[j];
    mu.swap(mn);
    out[j] = m.Bd.dot(mu);
  }
  return out;
}

// Linear convolution on a window of wn samples with a kernel given on the lags (-wn, wn):
// out[p] = sum_q ker(p - q) u[q], by FFTs of a 7-smooth length >= 2 wn - 1.
class WindowConvolver {
 public:
  explicit WindowConvolver(Index wn) : wn_(wn), q_(smooth_at_least(2 * wn - 1)), fft_(q_) {}

  template <typename Kernel>
  void set_kernel(const Kernel& ker) {
    VectorXd k = VectorXd::Zero(q_);
    for (Index m = -(wn_ - 1); m <= wn_ - 1; ++m) k[(m + q_) % q_] = ker(m);
    fft_.forward(k, &kernel_hat_);
  }

  MatrixXd apply(const MatrixXd& u) {
    MatrixXd out(wn_, u.cols());
    VectorXd buf = VectorXd::Zero(q_);
    VectorXcd spec;
    for (Index c = 0; c < u.cols(); ++c) {
      buf.head(wn_) = u.col(c);
      fft_.forward(buf, &spec);
      spec.array() *= kernel_hat_.array();
      out.col(c) = fft_.inverse(spec).head(wn_) / static_cast<double>(q_);
    }
    return out;
  }

 private:
  Index wn_;
  Index q_;
  signal::RealFft fft_;
  VectorXcd kernel_hat_;
};

// One exact solve at one alpha: the first P unknowns as a spectrum, the tail in time.
struct Evaluation {
  double alpha = 0.0;
  VectorXcd f_hat;  // DFT of f(0..P-1)
  VectorXd f_tail;  // f(P..M-1)
  double residual2 = 0.0;
  double norm2 = 0.0;
};

// The right-hand side of J(f) = ||G f - d||^2 + alpha ||f||^2 - 2 rho^T f (rho empty: 0).
struct Rhs {
  VectorXd d;       // M
  VectorXcd d_hat;  // DFT of d(0..P-1)
  VectorXd Oy;      // O^T d(0..P-1)
  VectorXd rho;     // M or empty
  VectorXcd rho_hat;
};

class ToeplitzTikhonov {
 public:
  ToeplitzTikhonov(const DiscreteModel& model, Index M, double decay_tolerance)
      : m_(model), n_(model.order()), M_(M), P_(even_smooth_at_most(M)), s_(M - P_), fft_(P_) {
    build_sequences(decay_tolerance);
    build_window();
  }

  Index P() const { return P_; }
  Index s() const { return s_; }
  Index L() const { return L_; }
  const Eigen::ArrayXd& eig2() const { return p_; }
  const Eigen::ArrayXd& weights() const { return w_; }

  Rhs make_rhs(const VectorXd& d) {
    Rhs r;
    r.d = d;
    fft_.forward(d.head(P_), &r.d_hat);
    VectorXd d_w(Wn_);
    for (Index p = 0; p < Wn_; ++p) d_w[p] = d[time_of(p)];
    r.Oy = O_w_.transpose() * d_w;
    return r;
  }

  Rhs make_residual_rhs(const VectorXd& rho) {
    Rhs r;
    r.d = VectorXd::Zero(M_);
    r.d_hat = VectorXcd::Zero(P_ / 2 + 1);
    r.Oy = VectorXd::Zero(n_);
    r.rho = rho;
    fft_.forward(rho.head(P_), &r.rho_hat);
    return r;
  }

  Evaluation solve(double alpha, const Rhs& rhs) {
    const bool has_rho = rhs.rho.size() > 0;
    const Index n = n_;
    // Tail: V(x(P)) = x^T Pi x - 2 q^T x + const, the cost of the last s rows and unknowns at
    // their optimum given x(P) (backward LQ tracking recursion; f_k = (sigma_k - g_k^T x)/gamma_k).
    MatrixXd Pi = MatrixXd::Zero(n, n);
    VectorXd q = VectorXd::Zero(n);
    MatrixXd tail_g(n, s_);
    VectorXd tail_sigma(s_), tail_gamma(s_);
    const MatrixXd CtC = m_.C.transpose() * m_.C;
    const MatrixXd At = m_.Ad.transpose();
    const VectorXd Ct = m_.C.transpose();
    MatrixXd Piw(n, n), PiwA(n, n);
    VectorXd qw(n), PiwB(n), g(n);
    for (Index k = M_ - 1; k >= P_; --k) {
      Piw = Pi + CtC;
      qw = q + Ct * rhs.d[k];
      PiwB.noalias() = Piw * m_.Bd;
      g.noalias() = At * PiwB;
      const double gamma = alpha + m_.Bd.dot(PiwB);
      const double sigma = m_.Bd.dot(qw) + (has_rho ? rhs.rho[k] : 0.0);
      tail_g.col(k - P_) = g;
      tail_sigma[k - P_] = sigma;
      tail_gamma[k - P_] = gamma;
      PiwA.noalias() = Piw * m_.Ad;
      Pi.noalias() = At * PiwA;
      Pi.noalias() -= g * (g.transpose() / gamma);
      Pi = 0.5 * (Pi + Pi.transpose()).eval();
      q.noalias() = At * qw;
      q -= g * (sigma / gamma);
    }
    const VectorXd v = q - Z_.transpose() * rhs.Oy;

    // Circulant part: f0 = D^-1 (C_P^T d + rho), D = C_P^T C_P + alpha I.
    const Index bins = P_ / 2 + 1;
    const double Pd = static_cast<double>(P_);
    const Eigen::ArrayXd inv = (p_ + alpha).inverse();
    VectorXcd f0_hat(bins);
    for (Index k = 0; k < bins; ++k) {
      cplx b = std::conj(lam_[k]) * rhs.d_hat[k];
      if (has_rho) b += rhs.rho_hat[k];
      f0_hat[k] = b * inv[k];
    }
    const VectorXd f0 = fft_.inverse(f0_hat) / Pd;
    VectorXd f0_w(Wn_);
    for (Index p = 0; p < Wn_; ++p) f0_w[p] = f0[time_of(p)];

    // Kernel of D^-1 on the window lags, W = D^-1 U on the window.
    const VectorXd kappa = fft_.inverse(inv.matrix().cast<cplx>()) / Pd;
    conv_->set_kernel([&](Index m) { return kappa[((m % P_) + P_) % P_]; });
    const MatrixXd W = conv_->apply(U_w_);

    // Woodbury: f = D^-1 b - D^-1 U (I + S U^T D^-1 U)^-1 S U^T D^-1 b, b = C^T d + rho + R^T v.
    const VectorXd Db_w = f0_w + W.leftCols(n) * v;
    MatrixXd S = MatrixXd::Zero(2 * n, 2 * n);
    S.topLeftCorner(n, n) = Z_.transpose() * Gamma_o_ * Z_ + Pi;
    S.topRightCorner(n, n) = -Z_.transpose();
    S.bottomLeftCorner(n, n) = -Z_;
    const MatrixXd cap = MatrixXd::Identity(2 * n, 2 * n) + S * (U_w_.transpose() * W);
    const VectorXd c = cap.partialPivLu().solve(S * (U_w_.transpose() * Db_w));
    const VectorXd g_w = R_w_ * v - U_w_ * c;  // f = f0 + D^-1 g
    const VectorXd f_w = Db_w - W * c;

    VectorXd g_full = VectorXd::Zero(P_);
    for (Index p = 0; p < Wn_; ++p) g_full[time_of(p)] = g_w[p];
    VectorXcd g_hat;
    fft_.forward(g_full, &g_hat);
    Evaluation ev;
    ev.alpha = alpha;
    ev.f_hat = f0_hat + (g_hat.array() * inv).matrix();

    // Norms of the first block: ||f||^2 and ||C_P f - d - O Z x(P)||^2 by Parseval and the
    // window (x(P) = R f, O^T (C_P f) = (C_P^T O)^T f).
    double e2 = 0.0, fa2 = 0.0;
    for (Index k = 0; k < bins; ++k) {
      e2 += w_[k] * std::norm(lam_[k] * ev.f_hat[k] - rhs.d_hat[k]);
      fa2 += w_[k] * std::norm(ev.f_hat[k]);
    }
    e2 /= Pd;
    fa2 /= Pd;
    VectorXd x = R_w_.transpose() * f_w;
    const VectorXd Ote = U2_w_.transpose() * f_w - rhs.Oy;
    const VectorXd zx = Z_ * x;
    double r2 = e2 - 2.0 * zx.dot(Ote) + zx.dot(Gamma_o_ * zx);

    // Tail, forward.
    ev.f_tail.resize(s_);
    double ft2 = 0.0;
    for (Index k = 0; k < s_; ++k) {
      const double f = (tail_sigma[k] - tail_g.col(k).dot(x)) / tail_gamma[k];
      x = m_.Ad * x + m_.Bd * f;
      const double r = rhs.d[P_ + k] - m_.C.dot(x);
      ev.f_tail[k] = f;
      ft2 += f * f;
      r2 += r * r;
    }
    ev.residual2 = std::max(r2, 0.0);
    ev.norm2 = fa2 + ft2;
    return ev;
  }

  VectorXd force(const Evaluation& ev) {
    VectorXd f(M_);
    f.head(P_) = fft_.inverse(ev.f_hat) / static_cast<double>(P_);
    f.tail(s_) = ev.f_tail;
    return f;
  }

  const VectorXcd& lambda() const { return lam_; }

 private:
  Index time_of(Index p) const { return (p - A_ + P_) % P_; }

  void build_sequences(double decay_tolerance) {
    const Index n = n_;
    // Rows C Ad^i and (Ad^i Bd)^T until the powers have decayed (decay length L <= P).
    std::vector<double> ob, rb;
    MatrixXd Apow = MatrixXd::Identity(n, n);
    double max_norm = Apow.norm();
    L_ = P_;
    for (Index i = 0; i < P_; ++i) {
      const Eigen::RowVectorXd o = m_.C * Apow;
      const VectorXd r = Apow * m_.Bd;
      ob.insert(ob.end(), o.data(), o.data() + n);
      rb.insert(rb.end(), r.data(), r.data() + n);
      Apow = m_.Ad * Apow;
      const double nm = Apow.norm();
      if (nm <= decay_tolerance * max_norm) {
        L_ = i + 1;
        break;
      }
      max_norm = std::max(max_norm, nm);
    }
    ob_ = Eigen::Map<const MatrixXd>(ob.data(), n, L_).transpose();
    rb_ = Eigen::Map<const MatrixXd>(rb.data(), n, L_).transpose();

    // K = (I - Ad^P)^-1, Z = Ad K; the periodized response h_P(i+1) = C Ad^i K Bd.
    MatrixXd AP = MatrixXd::Identity(n, n), base = m_.Ad;
    for (Index e = P_; e > 0; e >>= 1) {
      if (e & 1) AP = AP * base;
      base = base * base;
    }
    const MatrixXd K = (MatrixXd::Identity(n, n) - AP).partialPivLu().inverse();
    Z_ = m_.Ad * K;
    const VectorXd KB = K * m_.Bd;
    hp_ = ob_ * KB;  // L values; zero beyond
    VectorXd h = VectorXd::Zero(P_);
    h.head(L_) = hp_;
    fft_.forward(h, &lam_);
    p_ = lam_.array().abs2();
    w_ = half_spectrum_weights(P_);
  }

  void build_window() {
    const Index n = n_;
    if (2 * L_ <= P_) {
      A_ = L_;
      Wn_ = 2 * L_;
    } else {
      A_ = 0;
      Wn_ = P_;
    }
    O_w_ = MatrixXd::Zero(Wn_, n);
    R_w_ = MatrixXd::Zero(Wn_, n);
    for (Index p = 0; p < Wn_; ++p) {
      const Index t = time_of(p);
      if (t < L_) O_w_.row(p) = ob_.row(t);
      const Index m = P_ - 1 - t;  // R^T row t = (Ad^(P-1-t) Bd)^T
      if (m < L_) R_w_.row(p) = rb_.row(m);
    }
    Gamma_o_ = O_w_.transpose() * O_w_;
    conv_ = std::make_unique<WindowConvolver>(Wn_);
    // C_P^T O: (C_P^T o)_t = sum_i h_P(((i - t) mod P) + 1) o_i.
    conv_->set_kernel([&](Index m) {
      const Index lag = ((-m % P_) + P_) % P_;
      return lag < L_ ? hp_[lag] : 0.0;
    });
    U2_w_ = conv_->apply(O_w_);
    U_w_.resize(Wn_, 2 * n);
    U_w_ << R_w_, U2_w_;
  }

  const DiscreteModel& m_;
  Index n_, M_, P_, s_;
  Index L_ = 0, A_ = 0, Wn_ = 0;
  signal::RealFft fft_;
  std::unique_ptr<WindowConvolver> conv_;
  MatrixXd ob_, rb_;  // L x n
  VectorXd hp_;       // L
  MatrixXd Z_;
  VectorXcd lam_;     // eigenvalues of C_P, bins 0..P/2
  Eigen::ArrayXd p_;  // |lambda|^2
  Eigen::ArrayXd w_;  // Parseval weights
  MatrixXd O_w_, R_w_, U2_w_, U_w_, Gamma_o_;
};

struct Screen {
  std::vector<double> alpha, residual2, norm2, trace;
};

// Closed-form circulant screen over the grid (header: Tuning), blocked over bins so that the
// spectrum is read once for all alphas.
Screen circulant_screen(const std::vector<double>& alphas, const Eigen::ArrayXd& p,
                        const Eigen::ArrayXd& w, const VectorXcd& y_hat, Index P, Index M) {
  const Index bins = p.size(), K = static_cast<Index>(alphas.size());
  const Eigen::ArrayXd a = w * y_hat.array().abs2() / static_cast<double>(P);
  const Eigen::ArrayXd ap = a * p, wp = w * p;
  Eigen::ArrayXd s_res = Eigen::ArrayXd::Zero(K), s_norm = s_res, s_tr = s_res;
  constexpr Index kBlock = 2048;
  Eigen::ArrayXd inv(kBlock), inv2(kBlock);
  for (Index b0 = 0; b0 < bins; b0 += kBlock) {
    const Index len = std::min(kBlock, bins - b0);
    for (Index i = 0; i < K; ++i) {
      inv.head(len) = (p.segment(b0, len) + alphas[static_cast<size_t>(i)]).inverse();
      inv2.head(len) = inv.head(len).square();
      s_res[i] += (a.segment(b0, len) * inv2.head(len)).sum();
      s_norm[i] += (ap.segment(b0, len) * inv2.head(len)).sum();
      s_tr[i] += (wp.segment(b0, len) * inv.head(len)).sum();
    }
  }
  const double scale = static_cast<double>(M) / static_cast<double>(P);
  Screen s;
  s.alpha = alphas;
  for (Index i = 0; i < K; ++i) {
    const double al = alphas[static_cast<size_t>(i)];
    s.residual2.push_back(scale * al * al * s_res[i]);
    s.norm2.push_back(scale * s_norm[i]);
    s.trace.push_back(scale * s_tr[i]);
  }
  return s;
}

std::vector<double> alpha_grid(const DeconvolutionOptions& o) {
  const double l0 = std::log10(o.alpha_min), l1 = std::log10(o.alpha_max);
  const int count = static_cast<int>(std::floor((l1 - l0) * o.alphas_per_decade + 1e-9)) + 1;
  std::vector<double> a;
  for (int i = 0; i < count; ++i) a.push_back(std::pow(10.0, l0 + i / double(o.alphas_per_decade)));
  return a;
}

void check_options(const DeconvolutionOptions& o, double noise_var) {
  require_rule(std::isfinite(noise_var) && noise_var > 0.0, "rd.noise_var_N2", noise_var,
               "must be finite and > 0");
  require_rule(std::isfinite(o.alpha_min) && o.alpha_min > 0.0, "rd.alpha_min", o.alpha_min,
               "must be finite and > 0");
  require_rule(std::isfinite(o.alpha_max) && o.alpha_max > o.alpha_min, "rd.alpha_max", o.alpha_max,
               "must be finite and > alpha_min");
  require_rule(o.alphas_per_decade >= 1 && o.alphas_per_decade <= 1000, "rd.alphas_per_decade",
               o.alphas_per_decade, "must be 1..1000");
  require_rule(o.decay_tolerance > 0.0 && o.decay_tolerance < 1e-3, "rd.decay_tolerance",
               o.decay_tolerance, "must be in (0, 1e-3)");
  require_rule(o.tolerance > 0.0 && o.tolerance < 1.0, "rd.tolerance", o.tolerance,
               "must be in (0, 1)");
  require_rule(o.max_refinements >= 0, "rd.max_refinements", o.max_refinements, "must be >= 0");
  if (o.rule == AlphaRule::kFixed) {
    require_rule(std::isfinite(o.fixed_alpha) && o.fixed_alpha > 0.0, "rd_alpha", o.fixed_alpha,
                 "must be finite and > 0");
  }
}

template <typename Exact>
double choose_alpha(ToeplitzTikhonov& solver, const Rhs& rhs, Index M,
                    const DeconvolutionOptions& options, Exact& exact, DeconvolutionResult* res) {
  DeconvolutionResult& out = *res;
  // Screen.
  const std::vector<double> grid = alpha_grid(options);
  const Index K = static_cast<Index>(grid.size());
  const Screen scr =
      circulant_screen(grid, solver.eig2(), solver.weights(), rhs.d_hat, solver.P(), M);
  for (Index i = 0; i < K; ++i) {
    const size_t u = static_cast<size_t>(i);
    out.lcurve.push_back({grid[u], std::sqrt(scr.residual2[u]), std::sqrt(scr.norm2[u])});
  }

  // GCV on the screen.
  {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < grid.size(); ++i) {
      const double dof = static_cast<double>(M) - scr.trace[i];
      const double g = scr.residual2[i] / (dof * dof);
      if (std::isfinite(g) && g < best) {
        best = g;
        out.alpha_gcv = grid[i];
      }
    }
  }
  // L-curve corner: the largest signed curvature of (log ||r||, log ||f||) over log alpha.
  {
    double best = -std::numeric_limits<double>::infinity();
    for (size_t i = 1; i + 1 < grid.size(); ++i) {
      auto xr = [&](size_t j) { return 0.5 * std::log(scr.residual2[j]); };
      auto yn = [&](size_t j) { return 0.5 * std::log(scr.norm2[j]); };
      const double x1 = 0.5 * (xr(i + 1) - xr(i - 1)), y1 = 0.5 * (yn(i + 1) - yn(i - 1));
      const double x2 = xr(i + 1) - 2 * xr(i) + xr(i - 1), y2 = yn(i + 1) - 2 * yn(i) + yn(i - 1);
      const double kappa = (x1 * y2 - x2 * y1) / std::pow(x1 * x1 + y1 * y1, 1.5);
      if (std::isfinite(kappa) && kappa > best) {
        best = kappa;
        out.alpha_lcurve = grid[i];
      }
    }
  }
  // Discrepancy: screen, then exact walk to the bracket r2(a_i) <= T < r2(a_(i+1)).
  {
    const double T = out.discrepancy_target_N2;
    Index i = -1;
    for (Index j = 0; j < K; ++j) {
      if (scr.residual2[static_cast<size_t>(j)] <= T) i = j;
    }
    if (i < 0) i = 0;
    auto holds = [&](Index j) { return exact(grid[static_cast<size_t>(j)]).residual2 <= T; };
    if (holds(i)) {
      while (i + 1 < K && holds(i + 1)) ++i;
      out.discrepancy_satisfied = true;
    } else {
      while (i > 0 && !holds(i - 1)) --i;
      if (i > 0) {
        --i;
        out.discrepancy_satisfied = true;
      }
    }
    if (out.discrepancy_satisfied) {
      out.alpha_discrepancy = grid[static_cast<size_t>(i)];
      if (i + 1 == K) {
        out.summary.warnings.push_back(
            "rd: the discrepancy rule holds at the largest grid alpha; R may be too large");
      }
    }
  }

  // The chosen alpha.
  double alpha = out.alpha_discrepancy;
  switch (options.rule) {
    case AlphaRule::kDiscrepancy:
      if (!out.discrepancy_satisfied) {
        std::ostringstream w;
        w << "rd: no grid alpha satisfies the discrepancy rule ||G f - y||^2 <= (N - 1) R = "
          << out.discrepancy_target_N2 << " N^2 (residual^2 at alpha = " << grid.front() << ": "
          << exact(grid.front()).residual2 << " N^2); R too small or a wrong model; the GCV "
          << "alpha is used";
        out.summary.warnings.push_back(w.str());
        alpha = out.alpha_gcv;
        out.rule = AlphaRule::kGcv;
      }
      break;
    case AlphaRule::kGcv:
      alpha = out.alpha_gcv;
      break;
    case AlphaRule::kLcurve:
      alpha = out.alpha_lcurve;
      break;
    case AlphaRule::kFixed:
      alpha = options.fixed_alpha;
      break;
  }
  return alpha;
}

// The exact solution at alpha, checked by the state recursions and refined if needed.
DeconvolutionResult finish(const DiscreteModel& model, ToeplitzTikhonov& solver, const VectorXd& d,
                           double alpha, const Evaluation& first,
                           const DeconvolutionOptions& options, DeconvolutionResult out) {
  const Index M = d.size(), N = M + 1;
  VectorXd f = solver.force(first);
  const VectorXd Gtd = apply_toeplitz_transpose(model, d);
  const double Gtd_norm = Gtd.norm();
  VectorXd r = d - apply_toeplitz(model, f);
  auto normal_residual = [&]() -> VectorXd {
    return apply_toeplitz_transpose(model, r) - alpha * f;
  };
  VectorXd nu = normal_residual();
  out.relative_residual = Gtd_norm > 0.0 ? nu.norm() / Gtd_norm : nu.norm();
  while (out.relative_residual > options.tolerance && out.refinements < options.max_refinements) {
    f += solver.force(solver.solve(alpha, solver.make_residual_rhs(nu)));
    ++out.refinements;
    r = d - apply_toeplitz(model, f);
    nu = normal_residual();
    out.relative_residual = Gtd_norm > 0.0 ? nu.norm() / Gtd_norm : nu.norm();
  }
  out.residual_norm_N = r.norm();
  out.solution_norm_N = f.norm();
  out.force_N.resize(N);
  out.force_N.head(M) = f;
  out.force_N[N - 1] = f[M - 1];

  if (!(out.relative_residual <= options.tolerance)) {
    std::ostringstream m;
    m << "rd: not converged: relative normal-equation residual " << out.relative_residual
      << " > tolerance " << options.tolerance << " after " << out.refinements << " refinements";
    out.summary.fail(m.str());
    return out;
  }
  out.summary.succeed();
  std::ostringstream det;
  det << "alpha " << alpha << " (" << to_string(out.rule) << "); discrepancy "
      << out.alpha_discrepancy << ", gcv " << out.alpha_gcv << ", lcurve " << out.alpha_lcurve
      << "; FFT length " << out.fft_size << ", tail " << out.tail_length << ", decay length "
      << out.decay_length << "; relative residual " << out.relative_residual << " after "
      << out.refinements << " refinements";
  out.summary.details = det.str();
  return out;
}

// tune = false: one exact solve at options.fixed_alpha, no screen and no rules.
DeconvolutionResult run(const DiscreteModel& model, const Eigen::Ref<const Eigen::VectorXd>& y_N,
                        double noise_var_N2, const DeconvolutionOptions& options, bool tune) {
  const Index n = model.order();
  if (n < 1 || model.Ad.cols() != n || model.Bd.size() != n || model.C.size() != n) {
    throw std::invalid_argument("rd: model Ad must be square n x n with Bd, C of size n");
  }
  if (y_N.size() < 8) {
    throw std::invalid_argument("rd: the record has " + std::to_string(y_N.size()) +
                                " samples: needs at least 8");
  }
  check_options(options, noise_var_N2);
  const double radius = model.Ad.eigenvalues().cwiseAbs().maxCoeff();
  require_rule(radius < 1.0, "rd: model spectral radius of Ad", radius,
               "must be < 1 (a stable dynamometer model)");

  DeconvolutionResult out;
  out.rule = options.rule;
  if (!y_N.allFinite()) {
    out.summary.fail("rd: the record has non-finite samples");
    return out;
  }
  const Index N = y_N.size(), M = N - 1;
  const VectorXd d = y_N.tail(M);  // rows y(1..M)
  if (tune) out.discrepancy_target_N2 = static_cast<double>(M) * noise_var_N2;

  ToeplitzTikhonov solver(model, M, options.decay_tolerance);
  out.fft_size = solver.P();
  out.tail_length = solver.s();
  out.decay_length = solver.L();
  const Rhs rhs = solver.make_rhs(d);

  // Exact evaluations, kept for reuse by the final solve.
  std::deque<Evaluation> evals;  // references stay valid
  auto exact = [&](double alpha) -> const Evaluation& {
    for (const Evaluation& e : evals) {
      if (e.alpha == alpha) return e;
    }
    evals.push_back(solver.solve(alpha, rhs));
    const Evaluation& e = evals.back();
    out.exact.push_back({alpha, std::sqrt(e.residual2), std::sqrt(e.norm2)});
    return e;
  };
  double alpha = options.fixed_alpha;
  if (tune) alpha = choose_alpha(solver, rhs, M, options, exact, &out);
  if (!std::isfinite(alpha)) {
    out.summary.fail("rd: no alpha could be chosen by rule " +
                     std::string(to_string(options.rule)));
    return out;
  }
  out.alpha = alpha;
  const Evaluation& at_alpha = exact(alpha);
  return finish(model, solver, d, alpha, at_alpha, options, std::move(out));
}

}  // namespace

DeconvolutionResult deconvolve_tikhonov(const DiscreteModel& model,
                                        const Eigen::Ref<const Eigen::VectorXd>& y_N,
                                        double noise_var_N2, const DeconvolutionOptions& options) {
  return run(model, y_N, noise_var_N2, options, true);
}

DeconvolutionResult deconvolve_tikhonov_at(const DiscreteModel& model,
                                           const Eigen::Ref<const Eigen::VectorXd>& y_N,
                                           double alpha, const DeconvolutionOptions& options) {
  DeconvolutionOptions o = options;
  o.rule = AlphaRule::kFixed;
  o.fixed_alpha = alpha;
  return run(model, y_N, 1.0, o, false);
}

}  // namespace forcerec
}  // namespace chatterlab
