#include "analysis/sysid/spindle_drive.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/require.h"

namespace chatterlab {
namespace sysid {

namespace {

using cd = std::complex<double>;

constexpr int kMaxDelaySamples = 1000;
// The scan step of speed_loop_margins.
constexpr double kMarginScanHz = 0.5;

// Exact zero-order-hold discretization: exp([[A, B], [0, 0]] Ts) = [[Ad, Bd], [0, I]]. The
// states are first scaled by `scale` (a diagonal similarity) so that the augmented matrix is
// balanced for the scaling and squaring of Eigen's exp.
void zero_order_hold(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double Ts,
                     const Eigen::VectorXd& scale, Eigen::MatrixXd* Ad, Eigen::MatrixXd* Bd) {
  const Eigen::Index n = A.rows();
  const Eigen::Index m = B.cols();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + m, n + m);
  M.topLeftCorner(n, n) = scale.asDiagonal() * A * scale.cwiseInverse().asDiagonal() * Ts;
  M.topRightCorner(n, m) = scale.asDiagonal() * B * Ts;
  const Eigen::MatrixXd E = M.exp();
  *Ad = scale.cwiseInverse().asDiagonal() * E.topLeftCorner(n, n) * scale.asDiagonal();
  *Bd = scale.cwiseInverse().asDiagonal() * E.topRightCorner(n, m);
}

Eigen::MatrixXcd mimo_response(const DiscreteMimoSystem& s, cd z) {
  Eigen::MatrixXcd M = -s.A.cast<cd>();
  M.diagonal().array() += z;
  return s.C.cast<cd>() * M.partialPivLu().solve(s.B.cast<cd>()) + s.D.cast<cd>();
}

cd unit_z(double f_hz, double rate) { return std::polar(1.0, kTwoPi * f_hz / rate); }

}  // namespace

void validate(const SpindleDriveParams& p) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  require_rule(positive(p.j1_kg_m2), "j1_kg_m2", p.j1_kg_m2, "must be finite and > 0");
  require_rule(positive(p.j2_kg_m2), "j2_kg_m2", p.j2_kg_m2, "must be finite and > 0");
  require_rule(positive(p.k_nm_per_rad), "k_nm_per_rad", p.k_nm_per_rad, "must be finite and > 0");
  require_rule(non_negative(p.c_nm_s_per_rad), "c_nm_s_per_rad", p.c_nm_s_per_rad,
               "must be finite and >= 0");
  require_rule(non_negative(p.b_nm_s_per_rad), "b_nm_s_per_rad", p.b_nm_s_per_rad,
               "must be finite and >= 0");
  require_rule(positive(p.kt_nm_per_a), "kt_nm_per_a", p.kt_nm_per_a, "must be finite and > 0");
  require_rule(positive(p.current_bandwidth_rad_s), "current_bandwidth_rad_s",
               p.current_bandwidth_rad_s, "must be finite and > 0");
  require_rule(positive(p.kp_a_s_per_rad), "kp_a_s_per_rad", p.kp_a_s_per_rad,
               "must be finite and > 0");
  require_rule(positive(p.ti_s), "ti_s", p.ti_s, "must be finite and > 0");
  require_rule(positive(p.sample_rate_hz), "sample_rate_hz", p.sample_rate_hz,
               "must be finite and > 0");
  require_rule(non_negative(p.current_delay_s), "current_delay_s", p.current_delay_s,
               "must be finite and >= 0");
  const double samples = std::round(p.current_delay_s * p.sample_rate_hz);
  require_rule(std::abs(p.current_delay_s - samples / p.sample_rate_hz) <= 1e-9, "current_delay_s",
               p.current_delay_s, "must be a multiple of 1 / sample_rate_hz within 1e-9 s");
  require_rule(samples <= kMaxDelaySamples, "current_delay_s", p.current_delay_s,
               "must be at most 1000 samples");
}

Eigen::MatrixXcd frequency_response(const DiscreteMimoSystem& system, double f_hz) {
  return mimo_response(system, unit_z(f_hz, system.sample_rate_hz));
}

SpindleDrive::SpindleDrive(const SpindleDriveParams& params) : params_(params) {
  validate(params_);
  const SpindleDriveParams& p = params_;
  const double Ts = 1.0 / p.sample_rate_hz;
  delay_samples_ = static_cast<int>(std::lround(p.current_delay_s * p.sample_rate_hz));
  const int d = delay_samples_;

  // Continuous mechanics: states [th1 - th2, w1, w2], inputs [I_act (A), tau_d (N m)].
  const double J1 = p.j1_kg_m2, J2 = p.j2_kg_m2, k = p.k_nm_per_rad, c = p.c_nm_s_per_rad;
  Eigen::MatrixXd Am(3, 3);
  Am << 0.0, 1.0, -1.0,                               //
      -k / J1, -(p.b_nm_s_per_rad + c) / J1, c / J1,  //
      k / J2, c / J2, -c / J2;
  Eigen::MatrixXd Bm = Eigen::MatrixXd::Zero(3, 2);
  Bm(1, 0) = p.kt_nm_per_a / J1;
  if (p.disturbance_at_tool) {
    Bm(2, 1) = -1.0 / J2;
  } else {
    Bm(1, 1) = -1.0 / J1;
  }
  // Balance th1 - th2 against the speeds by the torsional frequency.
  const double wn = std::sqrt(k * (J1 + J2) / (J1 * J2));
  const double wc = p.current_bandwidth_rad_s;

  // Discrete plant: states [th1 - th2, w1, w2, I_act], inputs [I_nom[k-d], tau_d].
  Eigen::MatrixXd Ad = Eigen::MatrixXd::Zero(4, 4);
  Eigen::MatrixXd Bd = Eigen::MatrixXd::Zero(4, 2);
  if (p.current_loop == CurrentLoopForm::kSampledCurrent) {
    Eigen::MatrixXd Amd, Bmd;
    zero_order_hold(Am, Bm, Ts, Eigen::Vector3d(wn, 1.0, 1.0), &Amd, &Bmd);
    const double a = std::exp(-wc * Ts);
    Ad.topLeftCorner(3, 3) = Amd;
    Ad.block(0, 3, 3, 1) = Bmd.col(0);
    Ad(3, 3) = a;
    Bd(3, 0) = 1.0 - a;
    Bd.block(0, 1, 3, 1) = Bmd.col(1);
  } else {
    Eigen::MatrixXd Ac = Eigen::MatrixXd::Zero(4, 4);
    Eigen::MatrixXd Bc = Eigen::MatrixXd::Zero(4, 2);
    Ac.topLeftCorner(3, 3) = Am;
    Ac.block(0, 3, 3, 1) = Bm.col(0);
    Ac(3, 3) = -wc;
    Bc(3, 0) = wc;
    Bc.block(0, 1, 3, 1) = Bm.col(1);
    zero_order_hold(Ac, Bc, Ts, Eigen::Vector4d(wn, 1.0, 1.0, 1.0), &Ad, &Bd);
  }
  plant_.A = Ad;
  plant_.B = Bd;
  plant_.C = Eigen::MatrixXd::Zero(2, 4);
  plant_.C(0, 1) = 1.0;
  plant_.C(1, 3) = 1.0;
  plant_.D = Eigen::MatrixXd::Zero(2, 2);
  plant_.sample_rate_hz = p.sample_rate_hz;

  // Closed loop: states [plant (4), I_nom[k-1] .. I_nom[k-d], q].
  const int n = 4 + d + 1;
  const int iq = 4 + d;
  const double kp = kp_a_s_per_rad();
  const double ki = ki_a_per_rad();
  const double s = kRpmToRadPerS;
  Eigen::RowVectorXd K = Eigen::RowVectorXd::Zero(n);  // I_nom = K x + kr speed_ref_rpm
  K(1) = -kp;
  K(iq) = ki;
  const double kr = kp * s;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 2);
  A.topLeftCorner(4, 4) = Ad;
  B.block(0, 1, 4, 1) = Bd.col(1);
  if (d >= 1) {
    A.block(0, 3 + d, 4, 1) += Bd.col(0);
    A.row(4) = K;
    B(4, 0) = kr;
    for (int i = 1; i < d; ++i) A(4 + i, 3 + i) = 1.0;
  } else {
    A.topRows(4) += Bd.col(0) * K;
    B.block(0, 0, 4, 1) += Bd.col(0) * kr;
  }
  A(iq, iq) = 1.0;
  A(iq, 1) = -Ts;
  B(iq, 0) = Ts * s;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(3, n);
  C(0, 1) = 1.0 / s;
  C.row(1) = K;
  C(2, 3) = 1.0;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(3, 2);
  D(1, 0) = kr;
  closed_loop_.A = A;
  closed_loop_.B = B;
  closed_loop_.C = C;
  closed_loop_.D = D;
  closed_loop_.sample_rate_hz = p.sample_rate_hz;

  const double radius = closed_loop_poles().cwiseAbs().maxCoeff();
  require_rule(radius < 1.0, "closed-loop spectral radius", radius,
               "must be < 1 (the speed loop is unstable for these params)");
}

DiscreteStateSpace SpindleDrive::torque_to_current_model() const {
  DiscreteStateSpace m;
  m.A = closed_loop_.A;
  m.B = closed_loop_.B.col(1);
  m.C = closed_loop_.C.row(1);
  m.D = closed_loop_.D(1, 1);
  m.sample_rate_hz = closed_loop_.sample_rate_hz;
  return m;
}

Eigen::VectorXcd SpindleDrive::closed_loop_poles() const {
  return Eigen::EigenSolver<Eigen::MatrixXd>(closed_loop_.A, false).eigenvalues();
}

Eigen::VectorXcd SpindleDrive::torque_to_current(
    const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    G[i] = frequency_response(closed_loop_, f_hz[i])(1, 1);
  }
  return G;
}

Eigen::VectorXcd SpindleDrive::speed_tracking(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    G[i] = frequency_response(closed_loop_, f_hz[i])(0, 0);
  }
  return G;
}

SpindleDrive::PlantFrf SpindleDrive::plant_frf(double f_hz) const {
  const double rate = params_.sample_rate_hz;
  const cd z = unit_z(f_hz, rate);
  const Eigen::MatrixXcd P = mimo_response(plant_, z);
  PlantFrf r;
  r.w_rpm = P(0, 0) / kRpmToRadPerS;
  r.i = P(1, 0);
  r.delay = std::polar(1.0, -kTwoPi * f_hz * delay_samples_ / rate);
  r.controller = (kp_a_s_per_rad() + ki_a_per_rad() / (rate * (z - 1.0))) * kRpmToRadPerS;
  return r;
}

Eigen::VectorXcd SpindleDrive::open_loop_gain(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const PlantFrf r = plant_frf(f_hz[i]);
    G[i] = r.controller * r.delay * r.w_rpm;
  }
  return G;
}

Eigen::VectorXcd SpindleDrive::velocity_plant(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const PlantFrf r = plant_frf(f_hz[i]);
    G[i] = r.delay * r.w_rpm;
  }
  return G;
}

Eigen::VectorXcd SpindleDrive::mechanical(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const PlantFrf r = plant_frf(f_hz[i]);
    G[i] = r.w_rpm / r.i;
  }
  return G;
}

Eigen::VectorXcd SpindleDrive::current_loop(const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const PlantFrf r = plant_frf(f_hz[i]);
    G[i] = r.delay * r.i;
  }
  return G;
}

Eigen::VectorXcd SpindleDrive::speed_controller(
    const Eigen::Ref<const Eigen::VectorXd>& f_hz) const {
  Eigen::VectorXcd G(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) G[i] = plant_frf(f_hz[i]).controller;
  return G;
}

double SpindleDrive::dc_gain_torque_to_current() const {
  return dc_gain(torque_to_current_model());
}

SpeedLoopMargins SpindleDrive::speed_loop_margins() const {
  SpeedLoopMargins m;
  m.crossover_hz = std::numeric_limits<double>::quiet_NaN();
  m.phase_margin_deg = std::numeric_limits<double>::quiet_NaN();
  m.min_return_difference = std::numeric_limits<double>::infinity();
  const double nyquist = 0.5 * params_.sample_rate_hz;
  const auto loop_gain = [this](double f) {
    const PlantFrf r = plant_frf(f);
    return r.controller * r.delay * r.w_rpm;
  };
  double f_prev = 0.0;
  double mag_prev = std::numeric_limits<double>::infinity();
  for (double f = kMarginScanHz; f < nyquist; f += kMarginScanHz) {
    const cd L = loop_gain(f);
    const double rd = std::abs(1.0 + L);
    if (rd < m.min_return_difference) {
      m.min_return_difference = rd;
      m.min_return_difference_hz = f;
    }
    if (std::isnan(m.crossover_hz) && mag_prev > 1.0 && std::abs(L) <= 1.0) {
      double lo = f_prev, hi = f;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (std::abs(loop_gain(mid)) > 1.0 ? lo : hi) = mid;
      }
      m.crossover_hz = 0.5 * (lo + hi);
      m.phase_margin_deg = 180.0 + std::arg(loop_gain(m.crossover_hz)) * kRadToDeg;
    }
    f_prev = f;
    mag_prev = std::abs(L);
  }
  return m;
}

double SpindleDrive::torsional_frequency_hz() const {
  const SpindleDriveParams& p = params_;
  return std::sqrt(p.k_nm_per_rad * (p.j1_kg_m2 + p.j2_kg_m2) / (p.j1_kg_m2 * p.j2_kg_m2)) / kTwoPi;
}

double SpindleDrive::antiresonance_frequency_hz() const {
  return std::sqrt(params_.k_nm_per_rad / params_.j2_kg_m2) / kTwoPi;
}

SpindleDriveRecord SpindleDrive::simulate(const Eigen::VectorXd& speed_ref_rpm,
                                          const Eigen::VectorXd& tau_d_Nm) const {
  require_rule(speed_ref_rpm.size() == tau_d_Nm.size(), "tau_d_Nm length", tau_d_Nm.size(),
               "must equal the speed_ref_rpm length " + std::to_string(speed_ref_rpm.size()));
  require_rule(speed_ref_rpm.allFinite(), "speed_ref_rpm", "a non-finite sample", "must be finite");
  require_rule(tau_d_Nm.allFinite(), "tau_d_Nm", "a non-finite sample", "must be finite");
  const Eigen::Index N = speed_ref_rpm.size();
  SpindleDriveRecord rec;
  rec.speed_rpm.resize(N);
  rec.current_nom_a.resize(N);
  rec.current_act_a.resize(N);
  if (N == 0) return rec;
  const Eigen::MatrixXd& A = closed_loop_.A;
  const Eigen::MatrixXd& B = closed_loop_.B;
  const Eigen::MatrixXd& C = closed_loop_.C;
  const Eigen::MatrixXd& D = closed_loop_.D;
  const Eigen::Index n = A.rows();
  // Steady state of speed_ref_rpm[0], zero torque: x = A x + B u  =>  (I - A) x = B u.
  Eigen::VectorXd x =
      (Eigen::MatrixXd::Identity(n, n) - A).partialPivLu().solve(B.col(0) * speed_ref_rpm[0]);
  Eigen::VectorXd x_next(n);
  Eigen::VectorXd y(3);
  Eigen::Vector2d u;
  for (Eigen::Index k = 0; k < N; ++k) {
    u << speed_ref_rpm[k], tau_d_Nm[k];
    y.noalias() = C * x;
    y.noalias() += D * u;
    rec.speed_rpm[k] = y[0];
    rec.current_nom_a[k] = y[1];
    rec.current_act_a[k] = y[2];
    x_next.noalias() = A * x;
    x_next.noalias() += B * u;
    x.swap(x_next);
  }
  return rec;
}

}  // namespace sysid
}  // namespace chatterlab
