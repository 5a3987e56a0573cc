#include "analysis/sysid/torque_observer.h"

#include <Eigen/Dense>
#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/kalman/dare.h"

namespace chatterlab {
namespace sysid {

namespace {

void check_cut(const NominalCut& c, double rate) {
  require_rule(std::isfinite(rate) && rate > 0.0, "sample_rate_hz", rate, "must be > 0");
  require_rule(std::isfinite(c.spindle_rpm) && c.spindle_rpm > 0.0, "spindle_rpm", c.spindle_rpm,
               "must be > 0");
  require_rule(c.teeth >= 1 && c.teeth <= 100, "tool.teeth", c.teeth, "must be in 1..100");
  require_rule(std::isfinite(c.tool_radius_m) && c.tool_radius_m > 0.0, "tool.radius_mm",
               c.tool_radius_m * 1e3, "must be > 0");
  require_rule(std::isfinite(c.helix_deg) && c.helix_deg >= 0.0 && c.helix_deg <= 60.0,
               "tool.helix_deg", c.helix_deg, "must be in [0, 60]");
  require_rule(std::isfinite(c.axial_depth_m) && c.axial_depth_m > 0.0, "axial_depth_mm",
               c.axial_depth_m * 1e3, "must be > 0");
  require_rule(std::isfinite(c.radial_immersion_m) && c.radial_immersion_m > 0.0,
               "radial_immersion_mm", c.radial_immersion_m * 1e3, "must be > 0");
  require_rule(std::isfinite(c.feed_per_tooth_m) && c.feed_per_tooth_m > 0.0, "feed_per_tooth_mm",
               c.feed_per_tooth_m * 1e3, "must be > 0");
  require_rule(std::isfinite(c.Ktc_N_m2) && c.Ktc_N_m2 >= 0.0, "Ktc_N_m2", c.Ktc_N_m2,
               "must be >= 0");
  require_rule(std::isfinite(c.Kte_N_m) && c.Kte_N_m >= 0.0, "Kte_N_m", c.Kte_N_m, "must be >= 0");
}

}  // namespace

Eigen::VectorXd nominal_cutting_torque(const NominalCut& c, double rate, Eigen::Index samples) {
  check_cut(c, rate);
  require_rule(samples >= 0, "samples", samples, "must be >= 0");
  constexpr int kSlices = 100;
  const double R = c.tool_radius_m;
  const double D = 2.0 * R;
  const double dz = c.axial_depth_m / kSlices;
  const double tan_helix = std::tan(c.helix_deg * kDegToRad);
  double st = 0.0, ex = kPi;
  if (c.radial_immersion_m < 2.0 * R) {
    const double a = std::acos(1.0 - c.radial_immersion_m / R);
    if (c.up_milling) {
      st = 0.0;
      ex = a;
    } else {
      st = kPi - a;
      ex = kPi;
    }
  }
  Eigen::VectorXd lag(kSlices);
  for (int s = 0; s < kSlices; ++s) lag[s] = 2.0 * (s + 0.5) * dz * tan_helix / D;
  const double w = kTwoPi * c.spindle_rpm / 60.0;
  const double pitch = kTwoPi / c.teeth;
  Eigen::VectorXd T(samples);
  for (Eigen::Index k = 0; k < samples; ++k) {
    const double phi0 = w * static_cast<double>(k) / rate;
    double sum = 0.0;
    for (int j = 0; j < c.teeth; ++j) {
      for (int s = 0; s < kSlices; ++s) {
        double phi = std::fmod(phi0 + j * pitch - lag[s], kTwoPi);
        if (phi < 0.0) phi += kTwoPi;
        if (phi >= st && phi <= ex) {
          sum += c.Ktc_N_m2 * c.feed_per_tooth_m * std::sin(phi) + c.Kte_N_m;
        }
      }
    }
    T[k] = R * dz * sum;
  }
  return T;
}

double torque_increment_variance(const NominalCut& c, double rate) {
  check_cut(c, rate);
  const double samples = 20.0 * 60.0 / c.spindle_rpm * rate;
  require_rule(samples >= 10.0 && samples <= 2e6, "spindle_rpm", c.spindle_rpm,
               "twenty revolutions must span 10 to 2e6 samples at the sample rate (Q of the "
               "nominal cut)");
  const auto last = static_cast<Eigen::Index>(std::lround(samples));
  const Eigen::VectorXd T = nominal_cutting_torque(c, rate, last + 1);
  const Eigen::VectorXd w = T.tail(last) - T.head(last);
  const double mean = w.mean();
  return (w.array() - mean).square().sum() / static_cast<double>(last - 1);
}

TorqueObserver design_torque_observer(const DiscreteStateSpace& model, double Q, double R) {
  require_rule(std::isfinite(Q) && Q > 0.0, "Q_Nm2", Q, "must be finite and > 0");
  require_rule(std::isfinite(R) && R > 0.0, "R_A2", R, "must be finite and > 0");
  TorqueObserver o;
  o.model = model;
  o.Q_Nm2 = Q;
  o.R_A2 = R;
  const Eigen::Index n = model.order();
  const double g0 = dc_gain(model);
  if (!(std::abs(g0) >= 1e-9)) {
    o.summary.fail("the model's static gain is " + std::to_string(g0) +
                   ": a constant torque does not show in the current, so the torque state is "
                   "unobservable");
    return o;
  }
  const Eigen::Index m = n + 1;
  o.A_e = Eigen::MatrixXd::Zero(m, m);
  o.A_e.topLeftCorner(n, n) = model.A;
  o.A_e.topRightCorner(n, 1) = model.B;
  o.A_e(n, n) = 1.0;
  o.C_e.resize(m);
  o.C_e.head(n) = model.C;
  o.C_e(n) = model.D;
  Eigen::MatrixXd Qe = Eigen::MatrixXd::Zero(m, m);
  Qe(n, n) = Q;
  const Eigen::MatrixXd Rm = Eigen::MatrixXd::Constant(1, 1, R);
  const kalman::SteadyStateKalman ss = kalman::steady_state_gain(o.A_e, o.C_e, Qe, Rm);
  o.dare_residual = ss.residual;
  if (!ss.summary.ok()) {
    o.summary.fail("the steady-state gain failed: " + ss.summary.message);
    return o;
  }
  o.K = ss.K.col(0);
  const Eigen::MatrixXd F = (Eigen::MatrixXd::Identity(m, m) - o.K * o.C_e) * o.A_e;
  // Real block-diagonal modal form of F.
  Eigen::EigenSolver<Eigen::MatrixXd> es(F);
  if (es.info() == Eigen::Success) {
    const Eigen::VectorXcd lam = es.eigenvalues();
    const Eigen::MatrixXcd V = es.eigenvectors();
    o.spectral_radius = lam.cwiseAbs().maxCoeff();
    Eigen::MatrixXd T(m, m);
    Eigen::Index col = 0;
    bool ok = true;
    std::vector<int> blocks;
    for (Eigen::Index i = 0; i < m && ok; ++i) {
      const double scale = std::max(std::abs(lam[i]), 1e-300);
      if (std::abs(lam[i].imag()) <= 1e-12 * scale) {
        if (col + 1 > m) {
          ok = false;
          break;
        }
        T.col(col++) = V.col(i).real();
        blocks.push_back(1);
      } else if (lam[i].imag() > 0.0) {
        if (col + 2 > m) {
          ok = false;
          break;
        }
        T.col(col++) = V.col(i).real();
        T.col(col++) = V.col(i).imag();
        blocks.push_back(2);
      }
    }
    ok = ok && col == m;
    if (ok) {
      Eigen::PartialPivLU<Eigen::MatrixXd> lu(T);
      const Eigen::MatrixXd L = lu.solve(F * T);
      // Keep only the blocks; the rest must be rounding.
      Eigen::MatrixXd Lb = Eigen::MatrixXd::Zero(m, m);
      Eigen::Index at = 0;
      for (int b : blocks) {
        Lb.block(at, at, b, b) = L.block(at, at, b, b);
        at += b;
      }
      const double fnorm = std::max(F.norm(), 1e-300);
      o.modal_residual = (T * Lb - F * T).norm() / (fnorm * std::max(T.norm(), 1e-300));
      const double rcond = lu.rcond();
      if (o.modal_residual < 1e-10 && rcond > 1e-10) {
        o.modal = true;
        o.block_size = blocks;
        o.Lambda = Lb;
        o.b_modal = lu.solve(o.K);
        o.c_modal = T.row(n);
      }
    }
  }
  if (!o.modal) {
    o.summary.warnings.push_back(
        "the observer's eigenvectors are ill-conditioned: it runs in its dense form");
  }
  o.summary.succeed();
  return o;
}

void run_torque_observer_dense(const TorqueObserver& o, const Eigen::Ref<const Eigen::VectorXd>& y,
                               Eigen::VectorXd* torque) {
  const Eigen::Index m = o.A_e.rows();
  torque->resize(y.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd xp(m);
  if (y.size() > 0) (*torque)[0] = 0.0;  // x_0 = 0 (format step 4); y_0 is not used
  for (Eigen::Index k = 1; k < y.size(); ++k) {
    xp.noalias() = o.A_e * x;
    const double innov = y[k] - o.C_e.dot(xp);
    x = xp + o.K * innov;
    (*torque)[k] = x[m - 1];
  }
}

void run_torque_observer(const TorqueObserver& o, const Eigen::Ref<const Eigen::VectorXd>& y,
                         Eigen::VectorXd* torque) {
  if (!o.modal) {
    run_torque_observer_dense(o, y, torque);
    return;
  }
  const Eigen::Index m = o.Lambda.rows();
  torque->resize(y.size());
  // Flattened blocks: scalars (a, b, c) and pairs (p, q, b1, b2, c1, c2) with
  // [z1; z2] <- [[p, q], [-q, p]] [z1; z2] + [b1; b2] y (the real form of p + j q's rotation).
  std::vector<double> sa, sb, sc, pa, pq, pb1, pb2, pc1, pc2;
  Eigen::Index at = 0;
  for (int b : o.block_size) {
    if (b == 1) {
      sa.push_back(o.Lambda(at, at));
      sb.push_back(o.b_modal[at]);
      sc.push_back(o.c_modal[at]);
    } else {
      pa.push_back(o.Lambda(at, at));
      pq.push_back(o.Lambda(at, at + 1));
      pb1.push_back(o.b_modal[at]);
      pb2.push_back(o.b_modal[at + 1]);
      pc1.push_back(o.c_modal[at]);
      pc2.push_back(o.c_modal[at + 1]);
    }
    at += b;
  }
  (void)m;
  const std::size_t ns = sa.size(), np = pa.size();
  std::vector<double> zs(ns, 0.0), z1(np, 0.0), z2(np, 0.0);
  if (y.size() > 0) (*torque)[0] = 0.0;  // x_0 = 0 (format step 4); y_0 is not used
  for (Eigen::Index k = 1; k < y.size(); ++k) {
    const double u = y[k];
    double out = 0.0;
    for (std::size_t i = 0; i < ns; ++i) {
      zs[i] = sa[i] * zs[i] + sb[i] * u;
      out += sc[i] * zs[i];
    }
    for (std::size_t i = 0; i < np; ++i) {
      const double a1 = pa[i] * z1[i] + pq[i] * z2[i] + pb1[i] * u;
      const double a2 = -pq[i] * z1[i] + pa[i] * z2[i] + pb2[i] * u;
      z1[i] = a1;
      z2[i] = a2;
      out += pc1[i] * a1 + pc2[i] * a2;
    }
    (*torque)[k] = out;
  }
}

Eigen::VectorXcd torque_estimate_response(const TorqueObserver& o,
                                          const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  const Eigen::Index m = o.A_e.rows();
  const double rate = o.model.sample_rate_hz;
  const Eigen::VectorXcd G = frequency_response(o.model, f_hz);
  Eigen::VectorXcd H(f_hz.size());
  const Eigen::MatrixXd F = (Eigen::MatrixXd::Identity(m, m) - o.K * o.C_e) * o.A_e;
  Eigen::MatrixXcd M(m, m);
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const std::complex<double> z = std::polar(1.0, kTwoPi * f_hz[i] / rate);
    std::complex<double> h = 0.0;
    if (o.modal) {
      Eigen::Index at = 0;
      for (int b : o.block_size) {
        if (b == 1) {
          h += o.c_modal[at] * o.b_modal[at] / (z - o.Lambda(at, at));
        } else {
          // (zI - [[p, q], [-q, p]])^-1 = [[z - p, q], [-q, z - p]] / ((z - p)^2 + q^2)
          const double p = o.Lambda(at, at), q = o.Lambda(at, at + 1);
          const std::complex<double> d = (z - p) * (z - p) + q * q;
          const std::complex<double> v1 = ((z - p) * o.b_modal[at] + q * o.b_modal[at + 1]) / d;
          const std::complex<double> v2 = (-q * o.b_modal[at] + (z - p) * o.b_modal[at + 1]) / d;
          h += o.c_modal[at] * v1 + o.c_modal[at + 1] * v2;
        }
        at += b;
      }
    } else {
      M = -F.cast<std::complex<double>>();
      M.diagonal().array() += z;
      h = M.partialPivLu().solve(o.K.cast<std::complex<double>>())(m - 1);
    }
    H[i] = z * h * G[i];
  }
  return H;
}

double observer_bandwidth_hz(const TorqueObserver& o) {
  const double nyquist = 0.5 * o.model.sample_rate_hz;
  const Eigen::Index n = static_cast<Eigen::Index>(std::ceil(nyquist)) - 1;
  if (n < 1) return nyquist;
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(n, 1.0, static_cast<double>(n));
  const Eigen::VectorXcd H = torque_estimate_response(o, f);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (f[i] >= nyquist) break;
    if (std::abs(H[i]) < 1.0 / std::sqrt(2.0)) return f[i];
  }
  return nyquist;
}

}  // namespace sysid
}  // namespace chatterlab
