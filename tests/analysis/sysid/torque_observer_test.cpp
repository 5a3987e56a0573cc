// The torque observer of 001 ch. 4 (analysis/sysid/torque_observer.h).
#include "analysis/sysid/torque_observer.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/sysid/random_system.h"

namespace chatterlab {
namespace sysid {
namespace {

constexpr double kRate = 10000.0;

// 001's slot (sec. 5.1): 12 mm two-flute tool, 2 mm deep, 0.2 mm per tooth, Ktc = 797.6 N/mm^2,
// Kte = 25.7 N/mm, 3000 rpm.
NominalCut slot(double helix_deg) {
  NominalCut c;
  c.spindle_rpm = 3000.0;
  c.teeth = 2;
  c.tool_radius_m = 0.006;
  c.helix_deg = helix_deg;
  c.axial_depth_m = 0.002;
  c.radial_immersion_m = 0.012;
  c.feed_per_tooth_m = 0.2e-3;
  c.Ktc_N_m2 = 797.6e6;
  c.Kte_N_m = 25.7e3;
  return c;
}

// A torque-to-current model: a drive resonance at 700 Hz (zeta 0.05) and a real pole, static
// gain 1.25 A per N*m (= 1 / Kt with Kt = 0.8), realized at 10 kHz (state-space of the
// discretized transfer function by controllable form: 3 states).
DiscreteStateSpace drive_model() {
  const double wn = kTwoPi * 700.0, zeta = 0.05, Ts = 1.0 / kRate;
  const std::complex<double> s(-zeta * wn, wn * std::sqrt(1.0 - zeta * zeta));
  const std::complex<double> z1 = std::exp(s * Ts);
  const double p = std::exp(-kTwoPi * 300.0 * Ts);
  // Denominator (z - z1)(z - conj z1)(z - p) = z^3 + a1 z^2 + a2 z + a3.
  const double r2 = std::norm(z1), c2 = 2.0 * z1.real();
  const double a1 = -(c2 + p), a2 = r2 + c2 * p, a3 = -r2 * p;
  DiscreteStateSpace m;
  m.sample_rate_hz = kRate;
  m.A.resize(3, 3);
  m.A << -a1, -a2, -a3, 1, 0, 0, 0, 1, 0;
  m.B = Eigen::Vector3d(1, 0, 0);
  m.C = Eigen::RowVector3d(0, 0.5, 0.5);  // two zeros at -1 (bilinear-like numerator z + 1)
  m.D = 0.0;
  m.C *= 1.25 / dc_gain(m);
  return m;
}

// Reference: notes/001.md sec. 7.1, golden constants (computed there independently): slot
// torque mean 1.527 N*m and peak 2.223 N*m with helix 0; Q = 0.0021 (N*m)^2 (helix 0) and
// 0.0017 (helix 30) at 3000 rpm and 10 kHz. Tolerances: mean and peak to the printed digits
// (+- 0.5 in the last) plus the sampled peak's phase (0.2 %); Q within 5 % (the notes do not
// state their slicing or time grid).
TEST(NominalCut, SlotTorqueOf001) {
  const Eigen::VectorXd T = nominal_cutting_torque(slot(0.0), kRate, 2000);  // 100 revolutions/10
  EXPECT_NEAR(T.mean(), 1.527, 0.0015);
  EXPECT_NEAR(T.maxCoeff(), 2.223, 0.005);
  EXPECT_NEAR(torque_increment_variance(slot(0.0), kRate), 0.0021, 0.0021 * 0.05);
  EXPECT_NEAR(torque_increment_variance(slot(30.0), kRate), 0.0017, 0.0017 * 0.05);
  NominalCut bad = slot(0.0);
  bad.feed_per_tooth_m = 0.0;
  EXPECT_THROW(torque_increment_variance(bad, kRate), InputError);
  // Twenty revolutions must span 10 .. 2e6 samples: 1 rpm (1.2e7 samples) and 2e6 rpm are
  // refused, naming spindle_rpm.
  for (double rpm : {1.0, 2e6}) {
    NominalCut c = slot(0.0);
    c.spindle_rpm = rpm;
    try {
      torque_increment_variance(c, kRate);
      ADD_FAILURE() << rpm;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("spindle_rpm"), std::string::npos) << e.what();
    }
  }
}

// The DARE gain equals the limit of the time-varying Kalman filter on the augmented model
// (tolerance 1e-8 relative after 20,000 Riccati steps from P = I).
TEST(TorqueObserver, DareGainIsTheLimitOfTheTimeVaryingFilter) {
  const TorqueObserver o = design_torque_observer(drive_model(), 0.0021, 0.01 * 0.01 / 12.0);
  ASSERT_TRUE(o.summary.ok()) << o.summary.full_report();
  EXPECT_LT(o.dare_residual, 1e-9);
  const Eigen::Index m = o.A_e.rows();
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(m, m);
  Eigen::MatrixXd Qe = Eigen::MatrixXd::Zero(m, m);
  Qe(m - 1, m - 1) = o.Q_Nm2;
  Eigen::VectorXd K(m);
  for (int k = 0; k < 20000; ++k) {
    const double S = o.C_e * P * o.C_e.transpose() + o.R_A2;
    K = P * o.C_e.transpose() / S;
    const Eigen::MatrixXd Pp = P - K * o.C_e * P;
    P = o.A_e * Pp * o.A_e.transpose() + Qe;
  }
  EXPECT_LT((K - o.K).norm(), 1e-8 * o.K.norm()) << K.transpose() << "\n" << o.K.transpose();
}

// The modal recursion equals the dense one of the format's step 4 (1e-9 of the torque's range),
// the estimate's response to a constant torque is 1 (1e-9), and the bandwidth is where |H|
// first falls below 1/sqrt(2).
TEST(TorqueObserver, ModalEqualsDenseAndIsUnbiased) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    RandomSystemOptions ro;
    ro.order = 30;
    DiscreteStateSpace m = random_stable_system(ro, kRate, seed);
    const TorqueObserver o = design_torque_observer(m, 0.01, 8.33e-6);
    ASSERT_TRUE(o.summary.ok()) << o.summary.full_report();
    EXPECT_TRUE(o.modal) << seed;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd;
    Eigen::VectorXd y(20000);
    for (Eigen::Index k = 0; k < y.size(); ++k) y[k] = nd(rng);
    Eigen::VectorXd t1, t2;
    run_torque_observer(o, y, &t1);
    run_torque_observer_dense(o, y, &t2);
    EXPECT_EQ(t1[0], 0.0);  // x_0 = 0 (format step 4)
    EXPECT_EQ(t2[0], 0.0);
    const double range = t2.maxCoeff() - t2.minCoeff();
    EXPECT_LT((t1 - t2).cwiseAbs().maxCoeff(), 1e-9 * range) << seed;
    const Eigen::VectorXcd H0 = torque_estimate_response(o, Eigen::VectorXd::Zero(1));
    EXPECT_NEAR(std::abs(H0[0] - 1.0), 0.0, 1e-9) << seed;
    const double bw = observer_bandwidth_hz(o);
    ASSERT_GT(bw, 1.0);
    if (bw < 0.5 * kRate) {
      Eigen::VectorXd f(2);
      f << bw - 1.0, bw;
      const Eigen::VectorXcd H = torque_estimate_response(o, f);
      EXPECT_GE(std::abs(H[0]), 1.0 / std::sqrt(2.0));
      EXPECT_LT(std::abs(H[1]), 1.0 / std::sqrt(2.0));
    }
  }
}

TEST(TorqueObserver, AModelWithoutStaticGainIsUnobservable) {
  DiscreteStateSpace m = drive_model();
  m.C = Eigen::RowVector3d(1.0, -1.0, 0.0);  // numerator z - 1: zero at z = 1
  m.D = 0.0;
  ASSERT_LT(std::abs(dc_gain(m)), 1e-12);
  const TorqueObserver o = design_torque_observer(m, 0.01, 1e-5);
  EXPECT_TRUE(o.summary.failed());
  EXPECT_NE(o.summary.message.find("unobservable"), std::string::npos);
  EXPECT_THROW(design_torque_observer(drive_model(), 0.0, 1e-5), InputError);
}

// 001's slot at 3000, 5000 and 7000 rpm through the drive model, the current quantized to
// 0.01 A: the observer's torque NRMSE (001 eq. 4.20) against the true torque, after the first
// 0.05 s. Measured 8.0, 12.1 and 16.0 %: the error grows with speed as the tooth-passing
// harmonics approach the observer's bandwidth (1.7-1.8 kHz here), as 001 sec. 5.2 reports
// (10.4, 11.7, 18.2 % at 3000, 5000, 7000 rpm against a dynamometer). Bounds: the measured
// value plus 2 points.
TEST(TorqueObserver, SlotTorqueIsRecoveredFromQuantizedCurrent) {
  const DiscreteStateSpace m = drive_model();
  const std::pair<double, double> cases[] = {{3000.0, 10.0}, {5000.0, 14.0}, {7000.0, 18.0}};
  for (const auto& [rpm, bound] : cases) {
    NominalCut c = slot(30.0);
    c.spindle_rpm = rpm;
    const Eigen::Index n = 10000;
    const Eigen::VectorXd tau = nominal_cutting_torque(c, kRate, n);
    Eigen::VectorXd y(n);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(m.order());
    for (Eigen::Index k = 0; k < n; ++k) {
      y[k] = std::round(((m.C * x)(0) + m.D * tau[k]) / 0.01) * 0.01;
      x = m.A * x + m.B * tau[k];
    }
    const double Q = torque_increment_variance(c, kRate);
    const TorqueObserver o = design_torque_observer(m, Q, 0.01 * 0.01 / 12.0);
    ASSERT_TRUE(o.summary.ok());
    Eigen::VectorXd est;
    run_torque_observer(o, y, &est);
    const Eigen::Index k0 = 500;
    const Eigen::VectorXd e = est.tail(n - k0) - tau.tail(n - k0);
    const double rmse = std::sqrt(e.squaredNorm() / static_cast<double>(n - k0));
    const double range = tau.tail(n - k0).maxCoeff() - tau.tail(n - k0).minCoeff();
    const double nrmse = 100.0 * rmse / range;
    EXPECT_LT(nrmse, bound) << rpm << " rpm: NRMSE " << nrmse << " %, Q " << Q << ", bandwidth "
                            << observer_bandwidth_hz(o) << " Hz";
    RecordProperty(("nrmse_pct_" + std::to_string(static_cast<int>(rpm))).c_str(),
                   std::to_string(nrmse));
  }
}

}  // namespace
}  // namespace sysid
}  // namespace chatterlab
