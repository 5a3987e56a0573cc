#include "analysis/forcerec/smo.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/common/require.h"

namespace chatterlab {
namespace forcerec {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void check_shapes(Index n, Index cols, Index b, Index c, const char* who) {
  if (n < 2 || cols != n || b != n || c != n) {
    throw std::invalid_argument(std::string(who) +
                                ": the model must have a square A (order n >= 2), B of n rows "
                                "and C of n columns");
  }
}

// Tc = [N^T; C] of 004 eq. 2.17 and its inverse [N, C^T / |C|^2], N an orthonormal basis of
// null(C) (the last n-1 columns of the Householder Q of C^T).
void output_coordinates(const Eigen::RowVectorXd& C, MatrixXd* Tc, MatrixXd* Tc_inv,
                        const char* who) {
  const Index n = C.size();
  const double cn = C.norm();
  if (!(cn > 0.0) || !std::isfinite(cn)) {
    throw std::invalid_argument(std::string(who) + ": C must be finite and nonzero");
  }
  const MatrixXd N = orthogonal_complement(C.transpose());
  Tc->resize(n, n);
  Tc->topRows(n - 1) = N.transpose();
  Tc->row(n - 1) = C;
  Tc_inv->resize(n, n);
  Tc_inv->leftCols(n - 1) = N;
  Tc_inv->col(n - 1) = C.transpose() / (cn * cn);
}

// The roots of q(w) = (delta + w) f(w) = a w^2 + (a delta - rho - c) w - c delta, where
// f(w) = a w - rho w / (delta + w) - c is 2.21 on one side of e = 0 (w = |e|, c = sign(e) drive).
// With a < 0 and rho > 0 its discriminant (|a| delta + rho + c)^2 - 4 |a| c delta is > 0 (for
// c > 0 it exceeds (|a| delta - c)^2): two real roots, returned as (the root nearer 0, the other)
// without cancellation.
struct Roots {
  double near, far;
};
inline Roots quadratic_roots(double a, double delta, double rho, double c) {
  const double bq = a * delta - rho - c;
  const double cq = -c * delta;
  const double disc = bq * bq - 4.0 * a * cq;
  const double qq = -0.5 * (bq + std::copysign(std::sqrt(std::max(disc, 0.0)), bq));
  const double r1 = qq / a;
  const double r2 = qq != 0.0 ? cq / qq : r1;
  return std::abs(r1) <= std::abs(r2) ? Roots{r1, r2} : Roots{r2, r1};
}

// On the side where |e| falls to 0 (c > 0: both roots negative): w(t) for t < the crossing time,
// from time(w) = (1/a) [P1 ln((w - r1)/(w0 - r1)) + P2 ln((w - r2)/(w0 - r2))] = t, w in [0, w0]
// (time decreasing in w, time'(w) = 1 / f(w)). Safeguarded Newton.
double falling_side_end(double w0, double t, double a, double delta, double rho, double c,
                        const Roots& r, double P1, double P2) {
  auto f = [&](double w) { return a * w - rho * w / (delta + w) - c; };
  auto time = [&](double w) {
    return (P1 * std::log1p((w - w0) / (w0 - r.near)) + P2 * std::log1p((w - w0) / (w0 - r.far))) /
           a;
  };
  double lo = 0.0, hi = w0;  // time(lo) >= t >= time(hi)
  double w = std::clamp(w0 + t * f(w0), lo, hi);
  for (int it = 0; it < 100; ++it) {
    const double g = time(w) - t;
    if (g > 0.0) {
      lo = w;
    } else {
      hi = w;
    }
    double next = w - g * f(w);  // Newton: time'(w) = 1 / f(w)
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - w);
    w = next;
    if (step <= 1e-15 * w0 || hi - lo <= 1e-15 * w0) break;
  }
  return w;
}

// On the side holding the equilibrium w* >= 0 (c <= 0; w2 < 0 the other root): w(t) from w0.
// With u = (w - w*) / (w0 - w*) in (0, 1], P = (delta + w*)/(w* - w2), Q = (delta + w2)/(w2 - w*):
//   P ln u + Q ln(1 + r (u - 1)) = a t,   r = (w0 - w*) / (w0 - w2),
// monotone in v = ln u. Its root lies between a t / P and v_inf = (a t - Q ln(1 - r)) / P (the
// u -> 0 asymptote); when v_inf < -45, u < 1e-19 and w = w* to rounding.
double settling_side_end(double w0, double t, double a, double delta, double w_star, double w2) {
  const double m0 = w0 - w_star;
  if (m0 == 0.0) return w_star;
  const double r = m0 / (w0 - w2);
  const double P = (delta + w_star) / (w_star - w2);
  const double Q = (delta + w2) / (w2 - w_star);
  const double at = a * t;
  const double l = std::log1p(-r);
  const double v_inf = (at - Q * l) / P;
  if (v_inf < -45.0) return w_star;
  auto g = [&](double v) { return P * v + Q * std::log1p(r * std::expm1(v)) - at; };
  double lo = std::min(v_inf, at / P);
  double hi = std::min(0.0, std::max(v_inf, at / P));
  double v = std::clamp(v_inf, lo, hi);
  for (int it = 0; it < 100; ++it) {
    const double gv = g(v);
    if (gv > 0.0) {
      hi = v;
    } else {
      lo = v;
    }
    const double ev = std::exp(v);
    const double dg = P + Q * r * ev / (1.0 + r * std::expm1(v));
    double next = v - gv / dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - v);
    v = next;
    if (step <= 1e-14 * (1.0 + std::abs(v)) || hi - lo <= 1e-14 * (1.0 + std::abs(v))) break;
  }
  return w_star + std::exp(v) * m0;
}

// 2.21 with e1 = 0 over one interval, exactly (see smo.h). int nu dt = (e(dt) - e0) - a int e dt
// + b dt, and on each side (w = |e|, e = s w) int (w - r1) dt = (1/a) [(w_end - w_start) +
// (delta + r2) ln((w_end - r2)/(w_start - r2))] for either root r1 of q (the other r2): the
// integrand (w - r1)(delta + w) / q(w) = (1/a)(delta + w)/(w - r2).
inline OutputErrorStep step_impl(double e0, double b, double dt, double a, double delta,
                                 double rho) {
  double s;
  if (e0 > 0.0) {
    s = 1.0;
  } else if (e0 < 0.0) {
    s = -1.0;
  } else if (b == 0.0) {
    return {0.0, 0.0};
  } else {
    s = b > 0.0 ? -1.0 : 1.0;  // from e = 0, e' = -b
  }
  double w0 = std::abs(e0);
  double t = dt;
  double int_e = 0.0;
  double c = s * b;
  if (c > 0.0) {
    // |e| falls to 0: both roots negative.
    const Roots r = quadratic_roots(a, delta, rho, c);
    const double P1 = (delta + r.near) / (r.near - r.far);
    const double P2 = (delta + r.far) / (r.far - r.near);
    const double t_cross = -(P1 * std::log1p(w0 / -r.near) + P2 * std::log1p(w0 / -r.far)) / a;
    if (t_cross >= t) {
      const double wT = falling_side_end(w0, t, a, delta, rho, c, r, P1, P2);
      const double int_w =
          r.near * t + ((wT - w0) + (delta + r.far) * std::log1p((wT - w0) / (w0 - r.far))) / a;
      const double e = s * wT;
      return {e, ((e - e0) - a * s * int_w + b * dt) / dt};
    }
    const double int_w =
        r.near * t_cross + (-w0 + (delta + r.far) * std::log1p(-w0 / (w0 - r.far))) / a;
    int_e = s * int_w;
    t -= t_cross;
    s = -s;
    c = -c;
    w0 = 0.0;
  }
  // The side with the equilibrium w* >= 0 (c <= 0: roots of opposite signs, or 0).
  const Roots r = quadratic_roots(a, delta, rho, c);
  const double w_star = std::max(r.near, r.far);
  const double w2 = std::min(r.near, r.far);
  const double wT = settling_side_end(w0, t, a, delta, w_star, w2);
  const double I = ((wT - w0) + (delta + w2) * std::log1p((wT - w0) / (w0 - w2))) / a;
  int_e += s * (w_star * t + I);
  const double e = s * wT;
  return {e, ((e - e0) - a * int_e + b * dt) / dt};
}

void check_options(const SmoOptions& o) {
  require_rule(std::isfinite(o.rho_N_s) && o.rho_N_s > 0.0, "smo.rho_N_s", o.rho_N_s,
               "must be finite and > 0");
  require_rule(std::isfinite(o.delta_N) && o.delta_N > 0.0, "smo.delta_N", o.delta_N,
               "must be finite and > 0");
  require_rule(std::isfinite(o.a22s_1_s) && o.a22s_1_s < 0.0, "smo.a22s_1_s", o.a22s_1_s,
               "must be finite and < 0 (a stable output-error pole)");
  require_rule(std::isfinite(o.tooth_freq_hz) && o.tooth_freq_hz >= 0.0, "smo.tooth_freq_hz",
               o.tooth_freq_hz, "must be finite and >= 0");
  require_rule(o.harmonic_count >= 0, "smo.harmonic_count", o.harmonic_count, "must be >= 0");
  require_rule(std::isfinite(o.max_amplitude_error) && o.max_amplitude_error >= 0.0,
               "smo.max_amplitude_error", o.max_amplitude_error, "must be finite and >= 0");
}

std::string zeros_text(const Eigen::VectorXcd& z) {
  std::ostringstream m;
  m.precision(6);
  for (Index i = 0; i < z.size(); ++i) {
    if (i) m << ", ";
    m << z[i].real();
    if (z[i].imag() != 0.0) m << (z[i].imag() > 0 ? " + " : " - ") << std::abs(z[i].imag()) << "i";
  }
  return m.str();
}

}  // namespace

CanonicalForm canonical_form(const ContinuousModel& model) {
  const Index n = model.A.rows();
  check_shapes(n, model.A.cols(), model.B.size(), model.C.size(), "smo canonical_form");
  MatrixXd Tc, Tc_inv;
  output_coordinates(model.C, &Tc, &Tc_inv, "smo canonical_form");
  const VectorXd Bc = Tc * model.B;
  const double B2 = Bc[n - 1];  // = C B
  if (!(std::abs(B2) > 1e-12 * model.C.norm() * model.B.norm())) {
    throw std::invalid_argument(
        "smo canonical_form: C B = 0: the model is not of relative degree one (004 eq. 2.15)");
  }
  // 004 eq. 2.17 (E9): the upper-right block of Tb is -Bc(1:n-1) / Bc(n).
  MatrixXd Tb = MatrixXd::Identity(n, n), Tb_inv = MatrixXd::Identity(n, n);
  Tb.topRightCorner(n - 1, 1) = -Bc.head(n - 1) / B2;
  Tb_inv.topRightCorner(n - 1, 1) = Bc.head(n - 1) / B2;
  CanonicalForm out;
  out.T = Tb * Tc;
  const MatrixXd T_inv = Tc_inv * Tb_inv;
  out.A = out.T * model.A * T_inv;  // 004 eq. 2.16
  out.B = out.T * model.B;
  out.C = model.C * T_inv;
  out.B2 = B2;
  return out;
}

OneStepInverse one_step_inverse(const DiscreteModel& model) {
  const Index n = model.Ad.rows();
  check_shapes(n, model.Ad.cols(), model.Bd.size(), model.C.size(), "smo one_step_inverse");
  const Index m = n - 1;
  MatrixXd Tc, Tc_inv;
  output_coordinates(model.C, &Tc, &Tc_inv, "smo one_step_inverse");
  // z = Tc x, z(n-1) = y: y(k+1) = a21 z1(k) + a22 y(k) + h1 F(k), h1 = C Bd = h(1).
  const MatrixXd At = Tc * model.Ad * Tc_inv;
  const VectorXd Bt = Tc * model.Bd;
  const double h1 = Bt[m];
  if (!(std::abs(h1) > 1e-12 * model.C.norm() * model.Bd.norm())) {
    throw std::invalid_argument("smo one_step_inverse: C Bd = 0: y(k+1) does not see F(k)");
  }
  const MatrixXd A11 = At.topLeftCorner(m, m);
  const VectorXd a12 = At.topRightCorner(m, 1);
  const Eigen::RowVectorXd a21 = At.bottomLeftCorner(1, m);
  const double a22 = At(m, m);
  const VectorXd b1 = Bt.head(m);
  // F(k) = (y(k+1) - a21 z1(k) - a22 y(k)) / h1 in z1(k+1) = A11 z1 + a12 y(k) + b1 F(k).
  const MatrixXd M = A11 - b1 * a21 / h1;
  const Eigen::RealSchur<MatrixXd> schur(M);
  if (schur.info() != Eigen::Success) {
    throw std::runtime_error("smo one_step_inverse: the real Schur form did not converge");
  }
  const MatrixXd U = schur.matrixU();
  OneStepInverse inv;
  inv.S = schur.matrixT();
  inv.p = U.transpose() * (a12 - b1 * (a22 / h1));
  inv.q = U.transpose() * b1 / h1;
  inv.r = -(a21 * U) / h1;
  inv.d_prev = -a22 / h1;
  inv.d_next = 1.0 / h1;
  inv.sampled_zeros = Eigen::EigenSolver<MatrixXd>(M, false).eigenvalues();
  inv.max_zero_modulus = inv.sampled_zeros.cwiseAbs().maxCoeff();
  return inv;
}

void run_one_step_inverse(const OneStepInverse& inv, const Eigen::Ref<const Eigen::VectorXd>& y,
                          Eigen::Ref<Eigen::VectorXd> force) {
  const Index N = y.size();
  if (N < 2) throw std::invalid_argument("smo: the record needs N >= 2 samples");
  if (force.size() != N) throw std::invalid_argument("smo: force must have y.size() entries");
  const Index m = inv.S.rows();
  // Row-major copy of the quasi-triangular S: row i starts at column i - 1.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> S = inv.S;
  std::vector<double> w(static_cast<size_t>(m), 0.0), wn(static_cast<size_t>(m), 0.0);
  const double* Sd = S.data();
  const double* p = inv.p.data();
  const double* q = inv.q.data();
  const double* r = inv.r.data();
  const double dp = inv.d_prev, dn = inv.d_next;
  const double* yd = y.data();
  double* fd = force.data();
  double y_prev = 0.0;  // from rest: y(0) of the model is 0
  for (Index k = 0; k + 1 < N; ++k) {
    const double y_next = yd[k + 1];
    double F = dp * y_prev + dn * y_next;
    for (Index j = 0; j < m; ++j) F += r[j] * w[j];
    for (Index i = 0; i < m; ++i) {
      double acc = p[i] * y_prev + q[i] * y_next;
      const double* row = Sd + i * m;
      for (Index j = (i > 0 ? i - 1 : 0); j < m; ++j) acc += row[j] * w[j];
      wn[i] = acc;
    }
    w.swap(wn);
    fd[k] = F;
    y_prev = y_next;
  }
  fd[N - 1] = fd[N - 2];
}

OutputErrorStep smo_output_error_step(double e0_N, double drive_N_s, double dt_s,
                                      const SmoOptions& options) {
  check_options(options);
  require_rule(std::isfinite(dt_s) && dt_s > 0.0, "dt_s", dt_s, "must be finite and > 0");
  return step_impl(e0_N, drive_N_s, dt_s, options.a22s_1_s, options.delta_N, options.rho_N_s);
}

std::complex<double> smo_boundary_layer_response(const SmoOptions& options, double sample_rate_hz,
                                                 double f_hz, double reach_ratio) {
  const double m = std::clamp(reach_ratio, 0.0, 1.0);
  const double kappa = options.rho_N_s / options.delta_N * (1.0 - m) * (1.0 - m);
  const double lambda = kappa - options.a22s_1_s;
  const double x = lambda / sample_rate_hz;
  const double phi = std::exp(-x);
  const double beta = -std::expm1(-x) / x;
  const std::complex<double> z = std::polar(1.0, 2.0 * M_PI * f_hz / sample_rate_hz);
  return kappa / lambda * (1.0 - beta * (z - 1.0) / (z - phi));
}

SmoResult reconstruct_force_smo(const ContinuousModel& model, double sample_rate_hz,
                                const Eigen::Ref<const Eigen::VectorXd>& y,
                                const SmoOptions& options) {
  check_options(options);
  const Index N = y.size();
  if (N < 2) throw std::invalid_argument("smo: the record needs N >= 2 samples");
  SmoResult res;
  const CanonicalForm cf = canonical_form(model);
  res.B2_1_s = cf.B2;
  res.zeros_rad_s = Eigen::EigenSolver<MatrixXd>(cf.A11(), false).eigenvalues();
  const OneStepInverse inv = one_step_inverse(zoh(model, sample_rate_hz));
  res.sampled_zeros = inv.sampled_zeros;
  res.max_sampled_zero_modulus = inv.max_zero_modulus;
  res.corner_hz = options.rho_N_s / (2.0 * M_PI * options.delta_N);

  for (Index k = 0; k < N; ++k) {
    if (!std::isfinite(y[k])) {
      std::ostringstream m;
      m << "smo: y[" << k << "] = " << y[k] << ": not finite";
      res.summary.fail(m.str());
      return res;
    }
  }
  const double max_re_zero = res.zeros_rad_s.real().maxCoeff();
  if (!(max_re_zero < 0.0) || !(inv.max_zero_modulus < 1.0)) {
    std::ostringstream m;
    m << "smo: the model is not minimum phase";
    if (!(max_re_zero < 0.0)) m << " (a zero with Re >= 0: eig(A11) not Hurwitz)";
    if (!(inv.max_zero_modulus < 1.0)) {
      m << " (a sampled zero with |z| = " << inv.max_zero_modulus
        << " >= 1: the one-step inverse diverges)";
    }
    res.summary.fail(m.str(), "zeros (rad/s): " + zeros_text(res.zeros_rad_s) +
                                  "\nsampled zeros: " + zeros_text(inv.sampled_zeros));
    return res;
  }

  res.force.resize(N);
  res.output_error_N.resize(N);
  run_one_step_inverse(inv, y, res.force);  // F_zoh, overwritten by the estimate below

  const double B2 = cf.B2;
  res.reach_ratio = std::abs(B2) * res.force.cwiseAbs().maxCoeff() / options.rho_N_s;
  const double m_eff = std::min(res.reach_ratio, 1.0);
  const double kappa = options.rho_N_s / options.delta_N * (1.0 - m_eff) * (1.0 - m_eff);
  const double lambda = kappa - options.a22s_1_s;
  res.effective_corner_hz = lambda / (2.0 * M_PI);
  res.delay_samples = sample_rate_hz / lambda;
  if (options.tooth_freq_hz > 0.0 && options.harmonic_count > 0) {
    const double f = options.harmonic_count * options.tooth_freq_hz;
    res.amplitude_error =
        std::abs(std::abs(smo_boundary_layer_response(options, sample_rate_hz, f, m_eff)) - 1.0);
  }

  const double dt = 1.0 / sample_rate_hz;
  const double a = options.a22s_1_s, delta = options.delta_N, rho = options.rho_N_s;
  double* F = res.force.data();
  double* E = res.output_error_N.data();
  double e = 0.0;
  for (Index k = 0; k < N; ++k) {
    const OutputErrorStep st = step_impl(e, B2 * F[k], dt, a, delta, rho);
    e = st.e_end_N;
    F[k] = st.nu_mean_N_s / B2;
    E[k] = e;
  }
  if (!res.force.allFinite() || !res.output_error_N.allFinite()) {
    res.force.resize(0);
    res.output_error_N.resize(0);
    res.summary.fail("smo: the observer produced non-finite values");
    return res;
  }

  res.summary.succeed();
  std::ostringstream d;
  d << "B2 = " << B2 << " 1/s; zeros (rad/s): " << zeros_text(res.zeros_rad_s)
    << "; max |sampled zero| = " << inv.max_zero_modulus << "; rho/(2 pi delta) = " << res.corner_hz
    << " Hz, effective corner " << res.effective_corner_hz
    << " Hz, max|B2 F_zoh|/rho = " << res.reach_ratio << ", delay " << res.delay_samples
    << " samples";
  if (std::isfinite(res.amplitude_error)) {
    d << ", amplitude error at " << options.harmonic_count << " x " << options.tooth_freq_hz
      << " Hz = " << 100.0 * res.amplitude_error << " %";
  }
  res.summary.details = d.str();
  if (res.reach_ratio >= 1.0) {
    std::ostringstream w;
    w << "smo: rho = " << options.rho_N_s
      << " N/s is below max|B2 F_zoh| = " << res.reach_ratio * options.rho_N_s
      << " N/s: the observer cannot hold the sliding motion (004 eq. 2.21); the estimate is "
         "clipped and late";
    res.summary.warnings.push_back(w.str());
    res.bandwidth_warning = true;
  } else if (std::isfinite(res.amplitude_error) &&
             res.amplitude_error > options.max_amplitude_error) {
    std::ostringstream w;
    w << "smo: rho/delta = " << options.rho_N_s / options.delta_N
      << " 1/s is too small for the harmonics: the boundary layer changes the amplitude at "
      << options.harmonic_count << " x " << options.tooth_freq_hz << " Hz by "
      << 100.0 * res.amplitude_error << " % (> " << 100.0 * options.max_amplitude_error
      << " %) and delays by up to " << res.delay_samples << " samples";
    res.summary.warnings.push_back(w.str());
    res.bandwidth_warning = true;
  }
  return res;
}

}  // namespace forcerec
}  // namespace chatterlab
