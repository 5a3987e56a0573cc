// The SIFS compensator (analysis/sifs/compensator.h) on the synthetic 3-mode plant of
// notes/003.md section 7 (420 Hz / 0.03 / 0.55, 980 / 0.04 / 0.40, 2400 / 0.05 / 0.05; G(0) = 1),
// filter rate 10 kHz, 4 teeth: Van Loan against quadrature, the gain sequence against the DARE
// and against the project's generic KalmanFilter, the q/r invariance, the estimator response,
// compensation of an exactly simulated measured force, the tap sweep and the usable bandwidth.
#include "analysis/sifs/compensator.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <complex>
#include <random>
#include <sstream>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/kalman/dare.h"
#include "analysis/kalman/kalman_filter.h"
#include "tests/support/count_allocations.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab {
namespace sifs {
namespace {

using cd = std::complex<double>;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kFs = 10000.0;  // filter rate (003: Ts_filt = 1e-4 s)
constexpr int kTeeth = 4;
constexpr double kRpm = 9000.0;
constexpr double kSf = kRpm / 60.0;    // 150 Hz
constexpr double kTpf = kTeeth * kSf;  // 600 Hz

std::vector<SensorMode> plant() {
  return {{420.0, 0.03, 0.55}, {980.0, 0.04, 0.40}, {2400.0, 0.05, 0.05}};
}

// G(j 2 pi f) of 003 eq. 4-27, written out here (the reference for the model's response).
cd plant_response(const std::vector<SensorMode>& modes, double f_hz) {
  const double w = kTwoPi * f_hz;
  cd g = 0.0;
  for (const SensorMode& m : modes) {
    const double wn = kTwoPi * m.fn_hz;
    g += m.alpha * wn * wn / cd(wn * wn - w * w, 2.0 * m.zeta * wn * w);
  }
  return g;
}

// A_e of 003 eqs 4-50/4-51 as corrected (compensator.h), built here from the equations.
MatrixXd augmented(const std::vector<SensorMode>& modes, double tpf_hz) {
  const Index k = static_cast<Index>(modes.size()), n = 2 * k + 3;
  MatrixXd A = MatrixXd::Zero(n, n);
  for (Index i = 0; i < k; ++i) {
    const double w = kTwoPi * modes[static_cast<std::size_t>(i)].fn_hz;
    const double z = modes[static_cast<std::size_t>(i)].zeta;
    A.block(2 * i, 2 * i, 2, 2) << 0.0, w, -w, -2.0 * z * w;
    A(2 * i + 1, 2 * k) = w;
    A(2 * i + 1, 2 * k + 1) = w;
  }
  const double wt = kTwoPi * tpf_hz;
  A(2 * k + 1, 2 * k + 2) = -wt * wt;
  A(2 * k + 2, 2 * k + 1) = 1.0;
  return A;
}

// e^{A s} = V e^{Lambda s} V^-1 (A_e is diagonalizable: distinct eigenvalues), a second method
// independent of the Pade exponential.
struct EigenExp {
  explicit EigenExp(const MatrixXd& A) : es(A) { Vinv = es.eigenvectors().inverse(); }
  MatrixXd at(double s) const {
    const Eigen::VectorXcd e = (es.eigenvalues() * s).array().exp();
    return (es.eigenvectors() * e.asDiagonal() * Vinv).real();
  }
  Eigen::EigenSolver<MatrixXd> es;
  Eigen::MatrixXcd Vinv;
};

double relative_error(const MatrixXd& X, const MatrixXd& ref) {
  return (X - ref).norm() / ref.norm();
}

// The measured force of a periodic tip force f_a = c0 + sum_h Re(c_h e^{j h Omega t}) in
// periodic steady state: f_m = G(0) c0 + sum_h Re(G(j h Omega) c_h e^{j h Omega t}), exact at
// every sample (no discretisation).
struct PeriodicForce {
  double c0 = 0.0;
  std::vector<int> h;
  std::vector<cd> c;
  double at(double t) const {
    double f = c0;
    for (std::size_t i = 0; i < h.size(); ++i)
      f += std::real(c[i] * std::polar(1.0, h[i] * kTwoPi * kSf * t));
    return f;
  }
  double measured_at(const std::vector<SensorMode>& modes, double t) const {
    double f = plant_response(modes, 0.0).real() * c0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      f += std::real(plant_response(modes, h[i] * kSf) * c[i] *
                     std::polar(1.0, h[i] * kTwoPi * kSf * t));
    }
    return f;
  }
};

// Tooth-passing force with runout: strong TPF multiples (h = 4, 8) and smaller SF harmonics,
// several next to the modes (450 Hz by 420 Hz, 900 and 1050 Hz by 980 Hz).
[[maybe_unused]] PeriodicForce milling_force() {
  PeriodicForce f;
  f.c0 = 80.0;
  f.h = {1, 2, 3, 4, 5, 6, 7, 8};
  f.c = {cd(12.0, 5.0), cd(-6.0, 4.0),  cd(5.0, -3.0), cd(60.0, -35.0),
         cd(4.0, 2.0),  cd(-3.0, -2.0), cd(2.5, 1.5),  cd(-18.0, 12.0)};
  return f;
}

TEST(Compensator, VanLoanEqualsQuadratureOfTheIntegral) {
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  ASSERT_EQ(m.states, 9);
  const MatrixXd A = augmented(plant(), kTpf);
  const EigenExp E(A);
  const double T = 1.0 / kFs;
  MatrixXd GGt = MatrixXd::Zero(9, 9);  // Gamma Q_c Gamma^T, q = 1
  GGt(6, 6) = 1.0;
  GGt(7, 7) = 1.0;
  // Composite Simpson over [0, T] with 2000 intervals: the integrand's fastest term turns by
  // 2 |lambda|_max T ~ 3 rad over T, so the rule's error is ~ (3 / 2000)^4 / 180 ~ 3e-14.
  constexpr int kIntervals = 2000;
  MatrixXd Q = MatrixXd::Zero(9, 9);
  for (int i = 0; i <= kIntervals; ++i) {
    const double s = T * i / kIntervals;
    const double w = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const MatrixXd Es = E.at(s);
    Q += w * Es * GGt * Es.transpose();
  }
  Q *= T / (3.0 * kIntervals);
  // 1e-8 relative (Frobenius): the quadrature and the eigenvector route are good to ~1e-12.
  constexpr double kTolerance = 1e-8;
  EXPECT_LT(relative_error(m.Qd_unit, Q), kTolerance);
  EXPECT_LT(relative_error(m.F, E.at(T)), kTolerance);
  EXPECT_EQ((m.Qd_unit - m.Qd_unit.transpose()).cwiseAbs().maxCoeff(), 0.0);
  Eigen::RowVectorXd H(9), Co(9);
  H << 0.55, 0, 0.40, 0, 0.05, 0, 0, 0, 0;
  Co << 0, 0, 0, 0, 0, 0, 1, 1, 0;
  EXPECT_EQ(m.H, H);
  EXPECT_EQ(m.Co, Co);
  // Discrete observability (notes/003.md section 3: rcond 5e-10 .. 2e-8 for the 9-state pair).
  EXPECT_GT(m.obsv_rcond, 1e-12);
  EXPECT_TRUE(std::isfinite(m.cond_F));
  std::ostringstream rc;
  rc << m.obsv_rcond;
  ::testing::Test::RecordProperty("obsv_rcond", rc.str());
  ::testing::Test::RecordProperty("cond_F", std::to_string(m.cond_F));
}

// The prior covariance P- and gain of the project's generic KalmanFilter (kalman_filter.h) with
// Q = q Qd_unit, R = r from x0 = 0, P0 = 0, stepped until |K_k - K_k-1| <= 1e-14 |K_k|.
VectorXd generic_gain_limit(const CompensatorModel& m, double q, double r, int* steps) {
  kalman::LinearModel<9, 0, 1> lm;
  lm.A = m.F;
  lm.C = m.H;
  lm.Q = q * m.Qd_unit;
  lm.R(0, 0) = r;
  kalman::KalmanFilter<9, 0, 1> f(lm, kalman::Matrix<9, 1>::Zero(), kalman::Matrix<9, 9>::Zero());
  VectorXd K_prev = VectorXd::Zero(9), K(9);
  const kalman::Matrix<0, 1> u;
  const kalman::Matrix<1, 1> z = kalman::Matrix<1, 1>::Zero();
  for (*steps = 1; *steps <= 2000000; ++*steps) {
    f.predict(u);
    const kalman::Matrix<9, 1> PHt = f.covariance() * lm.C.transpose();
    K = PHt / ((lm.C * PHt)(0) + r);
    f.update(z);
    if ((K - K_prev).norm() <= 1e-14 * K.norm()) break;
    K_prev = K;
  }
  return K;
}

// The estimates C_o x+ of the generic KalmanFilter with Q = q Qd_unit, R = r, x0 = 0, P0 = 0.
template <int N>
VectorXd generic_estimates(const CompensatorModel& m, double q, double r, const VectorXd& zs) {
  kalman::LinearModel<N, 0, 1> lm;
  lm.A = m.F;
  lm.C = m.H;
  lm.Q = q * m.Qd_unit;
  lm.R(0, 0) = r;
  kalman::KalmanFilter<N, 0, 1> f(lm, kalman::Matrix<N, 1>::Zero(), kalman::Matrix<N, N>::Zero());
  VectorXd out(zs.size());
  const kalman::Matrix<0, 1> u;
  for (Index i = 0; i < zs.size(); ++i) {
    f.predict(u);
    f.update(kalman::Matrix<1, 1>::Constant(zs[i]));
    out[i] = m.Co.dot(f.state());
  }
  return out;
}

double max_relative_difference(const VectorXd& a, const VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// A measured cutting force: the exact steady-state response to milling_force() plus white
// noise of RMS sigma (seeded).
VectorXd measured_cut(Index samples, double sigma, unsigned seed, VectorXd* truth = nullptr) {
  const PeriodicForce fa = milling_force();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  VectorXd z(samples);
  if (truth != nullptr) truth->resize(samples);
  for (Index i = 0; i < samples; ++i) {
    const double t = static_cast<double>(i) / kFs;
    z[i] = fa.measured_at(plant(), t) + noise(rng);
    if (truth != nullptr) (*truth)[i] = fa.at(t);
  }
  return z;
}

TEST(Compensator, TimeVaryingGainConvergesToTheDareGain) {
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  const double q = std::ldexp(1.0, 9), r = 10.0;
  int steps = 0;
  const VectorXd K_seq = generic_gain_limit(m, q, r, &steps);
  const VectorXd K_inf = steady_gain(m, q / r);
  ASSERT_EQ(K_inf.size(), 9);
  // 1e-8 relative: the Riccati difference equation reaches its limit to ~1e-14, the SDA
  // solution is checked to 1e-13 in its own tests.
  EXPECT_LT((K_seq - K_inf).norm() / K_inf.norm(), 1e-8) << steps << " steps";
  ::testing::Test::RecordProperty("riccati_steps_q2e9_r10", steps);

  // compensate()'s held time-varying gain: on a record longer than the convergence, its
  // estimate equals the generic filter's (full covariance update every step) to 1e-10.
  const VectorXd z = measured_cut(steps + 20000, 1.0, 7);
  VectorXd est;
  const StepSummary s = compensate(m, q, r, GainMode::kTimeVarying, z, &est);
  ASSERT_TRUE(s.ok()) << s.full_report();
  EXPECT_TRUE(s.warnings.empty()) << s.full_report();
  EXPECT_LT(max_relative_difference(est, generic_estimates<9>(m, q, r, z)), 1e-10);
}

TEST(Compensator, EstimateDependsOnQOverROnly) {
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  const VectorXd z = measured_cut(30000, 3.0, 11);
  constexpr double kTolerance = 1e-10;  // rounding of two routes through ~1e4 steps
  for (const double a : {1e-3, 7.0, 1e4}) {
    const double q = std::ldexp(1.0, 12), r = 10.0;
    for (const GainMode g : {GainMode::kTimeVarying, GainMode::kSteadyState}) {
      VectorXd e1, e2;
      ASSERT_TRUE(compensate(m, q, r, g, z, &e1).ok());
      ASSERT_TRUE(compensate(m, a * q, a * r, g, z, &e2).ok());
      EXPECT_LT(max_relative_difference(e2, e1), kTolerance) << a << " " << to_string(g);
    }
    // The generic filter with the unscaled Q = a q Qd, R = a r (P scales by a, K does not).
    VectorXd e_tv;
    ASSERT_TRUE(compensate(m, q, r, GainMode::kTimeVarying, z, &e_tv).ok());
    EXPECT_LT(max_relative_difference(generic_estimates<9>(m, a * q, a * r, z), e_tv), kTolerance)
        << a;
    // The DARE with Q = a q Qd, R = a r against steady_gain(q / r).
    const kalman::SteadyStateKalman d =
        kalman::steady_state_gain(m.F, m.H, a * q * m.Qd_unit, MatrixXd::Constant(1, 1, a * r));
    ASSERT_TRUE(d.summary.ok());
    const VectorXd K = steady_gain(m, q / r);
    EXPECT_LT((d.K.col(0) - K).norm() / K.norm(), kTolerance) << a;
  }
}

TEST(Compensator, DynamicSizeAboveSixModesMatchesTheGenericFilter) {
  // k = 7: 17 states, the Eigen::Dynamic path.
  std::vector<SensorMode> modes = plant();
  for (const double f : {1300.0, 1700.0, 3000.0, 3600.0}) modes.push_back({f, 0.04, 0.0});
  for (SensorMode& mode : modes) mode.alpha = 1.0 / 7.0;
  const CompensatorModel m = make_compensator(modes, kTpf, kFs);
  ASSERT_EQ(m.states, 17);
  const VectorXd z = measured_cut(5000, 1.0, 3);
  VectorXd est;
  ASSERT_TRUE(compensate(m, 1e6, 1.0, GainMode::kTimeVarying, z, &est).ok());
  // 1e-9: 17 states at q/r = 1e6, the two routes' rounding differs by ~4e-10 of the peak.
  EXPECT_LT(max_relative_difference(est, generic_estimates<17>(m, 1e6, 1.0, z)), 1e-9);
}

TEST(Compensator, TheDataLoopAllocatesNothing) {
  if (!kCountingMalloc) GTEST_SKIP() << "allocation counting is off under AddressSanitizer";
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  for (const GainMode g : {GainMode::kSteadyState, GainMode::kTimeVarying}) {
    long counts[2];
    const Index lengths[2] = {60000, 600000};  // both beyond the gain's convergence at q/r 1e5
    for (int i = 0; i < 2; ++i) {
      const VectorXd z = VectorXd::Constant(lengths[i], 1.0);
      VectorXd est(lengths[i]);
      testing::g_allocations = 0;
      testing::g_counting = true;
      const StepSummary s = compensate(m, 1e6, 10.0, g, z, &est);
      testing::g_counting = false;
      ASSERT_TRUE(s.ok());
      counts[i] = testing::g_allocations;
    }
    EXPECT_EQ(counts[0], counts[1]) << to_string(g);  // no allocation per sample
  }
}

TEST(Compensator, EstimatorResponseIsOneAtDcAndAtTheToothPassingFrequency) {
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  constexpr double kTolerance = 1e-6;
  for (const int n : {9, 15, 21}) {
    const VectorXd K = steady_gain(m, std::ldexp(1.0, n) / 10.0);
    ASSERT_EQ(K.size(), 9);
    // The random walk and the TPF resonator are internal models: a constant or a TPF
    // sinusoid in f_m is reproduced with no error, T G = 1 there (G(0) = 1 for this plant).
    EXPECT_LT(std::abs(estimator_response(m, K, 0.0) - 1.0), kTolerance) << n;
    EXPECT_LT(std::abs(estimator_response(m, K, kTpf) * plant_response(plant(), kTpf) - 1.0),
              kTolerance)
        << n;
  }
  // notes/003.md section 7 item 5 at q = 2^9, R = 10, 9000 rpm: 0.60, 0.35, 0.21 at the 1st-3rd
  // SF harmonics. Computed here: they are |T G| (the total response, notes section 5), not |T|
  // (0.548, 0.221, 0.071); to the notes' two digits.
  const VectorXd K9 = steady_gain(m, std::ldexp(1.0, 9) / 10.0);
  const double notes[3] = {0.60, 0.35, 0.21};
  for (int h = 1; h <= 3; ++h) {
    const cd T = estimator_response(m, K9, h * kSf);
    const double tg = std::abs(T * plant_response(plant(), h * kSf));
    EXPECT_NEAR(tg, notes[h - 1], 0.01) << "h = " << h;
    ::testing::Test::RecordProperty("abs_T_h" + std::to_string(h), std::to_string(std::abs(T)));
    ::testing::Test::RecordProperty("abs_TG_h" + std::to_string(h), std::to_string(tg));
  }
  // Between DC and the TPF |T G| < 1 for q = 2^9 (the estimate under-reads, "left of the
  // optimum"); for large q it exceeds 1 somewhere below Nyquist (over-reads).
  double max_small = 0.0, max_large = 0.0;
  const VectorXd K30 = steady_gain(m, std::ldexp(1.0, 30) / 10.0);
  ASSERT_EQ(K30.size(), 9);
  for (double f = 1.0; f < kTpf; f += 1.0) {
    max_small =
        std::max(max_small, std::abs(estimator_response(m, K9, f) * plant_response(plant(), f)));
  }
  for (double f = 1.0; f < 0.5 * kFs; f += 1.0) {
    max_large =
        std::max(max_large, std::abs(estimator_response(m, K30, f) * plant_response(plant(), f)));
  }
  EXPECT_LT(max_small, 1.0);
  EXPECT_GT(max_large, 1.1);
  ::testing::Test::RecordProperty("max_TG_q2e30", std::to_string(max_large));
}

TEST(Compensator, EstimatorResponseMatchesTheFilteredSinusoid) {
  // The steady-state filter run on z = cos(2 pi f t): after the transient its output is
  // Re(T e^{j 2 pi f t}); the fitted phasor against T at 1e-6 relative (transient and fit
  // rounding far below).
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  const double q = std::ldexp(1.0, 21), r = 10.0;
  const VectorXd K = steady_gain(m, q / r);
  for (const double f : {150.0, 450.0, 1250.0}) {
    constexpr Index kSamples = 200000;
    VectorXd z(kSamples), est;
    for (Index i = 0; i < kSamples; ++i) z[i] = std::cos(kTwoPi * f * static_cast<double>(i) / kFs);
    ASSERT_TRUE(compensate(m, q, r, GainMode::kSteadyState, z, &est).ok());
    // The last 20000 samples (2 s) hold whole periods of f / 50 Hz.
    const Eigen::VectorXcd c = cut_harmonics(est, kFs, kSamples - 20000, kSamples, f / 50.0, {50});
    const cd T = estimator_response(m, K, f);
    EXPECT_LT(std::abs(c[0] - T) / std::abs(T), 1e-6) << f;
  }
}

TEST(Compensator, CompensationRecoversTheTipForceHarmonics) {
  // 9000 rpm, 4 teeth: the TPF (600 Hz) sits by the antiresonance (|G| = 0.19), h = 3 (450 Hz)
  // by the 420 Hz mode (|G| = 2.9), h = 6, 7 (900, 1050 Hz) by the 980 Hz mode.
  constexpr double kSigma = 3.0;  // N, R = the RMS as the format prescribes
  constexpr Index kSamples = 50000, kBegin = 20000, kEnd = 50000;  // 450 whole revolutions
  VectorXd truth;
  const VectorXd z = measured_cut(kSamples, kSigma, 5, &truth);
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  const std::vector<int> h = analysed_harmonics(kSf, 10.0, 4000.0, kFs);
  ASSERT_EQ(h.size(), 26u);  // 150 .. 3900 Hz
  const Eigen::VectorXcd c_ref = cut_harmonics(truth, kFs, kBegin, kEnd, kSf, h);
  const SweepCurve curve =
      cut_sweep(m, kSigma, GainMode::kTimeVarying, z, kBegin, kEnd, kSf, h, c_ref);
  ASSERT_TRUE(curve.summary.ok()) << curve.summary.full_report();
  VectorXd est;
  ASSERT_TRUE(compensate(m, curve.q_opt, kSigma, GainMode::kTimeVarying, z, &est).ok());
  const Eigen::VectorXcd c_est = cut_harmonics(est, kFs, kBegin, kEnd, kSf, h);
  const Eigen::VectorXcd c_meas = cut_harmonics(z, kFs, kBegin, kEnd, kSf, h);
  EXPECT_NEAR(spectral_rmse(c_est, c_ref),
              curve.rmse_n[curve.best_exponent - curve.exponents.front()], 1e-12);
  // Amplitude errors in % at the harmonics carrying the force (h = 1..8).
  double rms_comp = 0.0, rms_meas = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double ref = std::abs(c_ref[i]);
    const double e_comp = 100.0 * (std::abs(c_est[i]) - ref) / ref;
    const double e_meas = 100.0 * (std::abs(c_meas[i]) - ref) / ref;
    ::testing::Test::RecordProperty("amp_err_pct_h" + std::to_string(i + 1),
                                    std::to_string(e_meas) + " -> " + std::to_string(e_comp));
    rms_comp += e_comp * e_comp / 8.0;
    rms_meas += e_meas * e_meas / 8.0;
  }
  rms_comp = std::sqrt(rms_comp);
  rms_meas = std::sqrt(rms_meas);
  ::testing::Test::RecordProperty("cut_q_opt_exponent", curve.best_exponent);
  ::testing::Test::RecordProperty("amp_err_rms_pct",
                                  std::to_string(rms_meas) + " -> " + std::to_string(rms_comp));
  EXPECT_LT(rms_comp, 0.2 * rms_meas);
  // At the TPF the resonator makes T G = 1 whatever q: only noise remains (~0.03 N of 69 N).
  EXPECT_LT(std::abs(std::abs(c_est[3]) / std::abs(c_ref[3]) - 1.0), 0.005);
  EXPECT_LT(spectral_rmse(c_est, c_ref), 0.2 * spectral_rmse(c_meas, c_ref));
}

// Synthetic taps: 3 hits of a 0.6 ms half-sine (peak 200 N) 30 ms into 0.2048 s windows; the
// sensor force from the exact zero-order-hold discretisation of the plant (the hammer held over
// each sample), plus seeded white noise of RMS 0.15 N (R_tap, 003 sec. 6.1).
TapSweepInput synthetic_taps(const std::vector<SensorMode>* modes) {
  constexpr Index kWindow = 2048, kImpact = 300, kHits = 3;
  const Index k = static_cast<Index>(modes->size());
  // [[A_n, B_n], [0, 0]] (A_e's leading block): its exponential holds Phi and the ZOH Gamma.
  const MatrixXd Aug = augmented(*modes, kTpf).topLeftCorner(2 * k + 1, 2 * k + 1);
  const MatrixXd E = (Aug / kFs).exp();
  const MatrixXd Phi = E.topLeftCorner(2 * k, 2 * k);
  const VectorXd Gam = E.topRightCorner(2 * k, 1);
  Eigen::RowVectorXd C = Eigen::RowVectorXd::Zero(2 * k);
  for (Index i = 0; i < k; ++i) C(2 * i) = (*modes)[static_cast<std::size_t>(i)].alpha;
  TapSweepInput in;
  in.modes = modes;
  in.hammer_n = VectorXd::Zero(kWindow * kHits);
  for (Index w = 0; w < kHits; ++w) {
    for (Index i = 0; i < 6; ++i) {
      in.hammer_n[w * kWindow + kImpact + i] = 200.0 * std::sin(kPi * (i + 0.5) / 6.0);
    }
    in.windows.push_back({w * kWindow, (w + 1) * kWindow});
    in.pre_end.push_back(kImpact - 10);  // 1 ms before the impact
  }
  std::mt19937_64 rng(17);
  std::normal_distribution<double> noise(0.0, 0.15);
  in.response_n.resize(in.hammer_n.size());
  VectorXd x = VectorXd::Zero(2 * k);
  for (Index i = 0; i < in.hammer_n.size(); ++i) {
    in.response_n[i] = C.dot(x) + noise(rng);
    x = Phi * x + Gam * in.hammer_n[i];
  }
  in.filter_rate_hz = kFs;
  in.r_tap_n = 0.15;
  in.band_lo_hz = 10.0;
  in.band_hi_hz = 4000.0;
  return in;
}

TEST(Compensator, TapSweepFindsAFlatMinimum) {
  const std::vector<SensorMode> modes = plant();
  const TapSweepInput in = synthetic_taps(&modes);
  const SweepCurve c = tap_sweep(in, kRpm, kTeeth);
  ASSERT_TRUE(c.summary.ok()) << c.summary.full_report();
  ASSERT_EQ(c.rmse_n.size(), 30);
  EXPECT_EQ(c.exponents.front(), 1);
  EXPECT_EQ(c.exponents.back(), 30);
  EXPECT_TRUE(c.rmse_n.allFinite());
  const double min = c.rmse_n.minCoeff();
  const Index best = c.best_exponent - 1;
  EXPECT_EQ(c.q_opt, std::ldexp(1.0, c.best_exponent));
  EXPECT_LE(c.rmse_n[best], 1.005 * min);  // the 0.5 % rule
  for (Index i = 0; i < best; ++i) EXPECT_GT(c.rmse_n[i], 1.005 * min) << i + 1;
  EXPECT_LT(min, 0.5 * c.rmse_n[0]);  // a real minimum, well below the smallest q

  // The RMSE at q_opt recomputed here from its definition (format step 4) with complex sums.
  VectorXd est;
  ASSERT_TRUE(compensate(make_compensator(modes, kTpf, kFs), c.q_opt, in.r_tap_n,
                         GainMode::kTimeVarying, in.response_n, &est)
                  .ok());
  double sum = 0.0;
  for (std::size_t w = 0; w < in.windows.size(); ++w) {
    const Index b = in.windows[w].begin, L = in.windows[w].end - b;
    const double me = est.segment(b, in.pre_end[w]).mean();
    const double mh = in.hammer_n.segment(b, in.pre_end[w]).mean();
    double ss = 0.0;
    for (const int h : c.harmonics) {
      cd xe = 0.0, xh = 0.0;
      for (Index i = 0; i < L; ++i) {
        const cd e = std::polar(1.0, -kTwoPi * h * kSf * static_cast<double>(i) / kFs);
        xe += (est[b + i] - me) * e;
        xh += (in.hammer_n[b + i] - mh) * e;
      }
      const double d = 2.0 / static_cast<double>(L) * (std::abs(xe) - std::abs(xh));
      ss += d * d;
    }
    sum += std::sqrt(ss / static_cast<double>(c.harmonics.size()));
  }
  EXPECT_NEAR(c.rmse_n[best], sum / 3.0, 1e-9 * sum);
}

TEST(Compensator, TapMapEqualsOneSweepPerSpeed) {
  const std::vector<SensorMode> modes = plant();
  const TapSweepInput in = synthetic_taps(&modes);
  const std::vector<double> rpm = {4500.0, 9000.0, 11600.0};
  SweepOptions o;
  o.n_first = 5;
  o.n_last = 20;
  const TapMap map = tap_map(in, rpm, kTeeth, 2, o);
  ASSERT_EQ(map.rmse_n.rows(), 3);
  ASSERT_EQ(map.rmse_n.cols(), 16);
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    const SweepCurve c = tap_sweep(in, rpm[i], kTeeth, o);
    EXPECT_EQ(map.rmse_n.row(static_cast<Index>(i)), c.rmse_n.transpose()) << rpm[i];
    EXPECT_EQ(map.best_exponent[i], c.best_exponent);
  }
}

TEST(Compensator, UsableBandwidthBeforeAndAfter) {
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  // Before: |G| rises from 1 at DC to the 420 Hz peak; the first 1 Hz grid point at or past
  // the root of |G(f)| = 1.1, found here by bisection, is the answer.
  double lo = 1.0, hi = 400.0;
  ASSERT_LT(std::abs(plant_response(plant(), lo)), 1.1);
  ASSERT_GT(std::abs(plant_response(plant(), hi)), 1.1);
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::abs(plant_response(plant(), mid)) < 1.1 ? lo : hi) = mid;
  }
  // And a brute-force scan of ||G| - 1| >= 0.1 at 0.01 Hz over (0, 400] finds the same root.
  double first = 0.0;
  for (int i = 1; i <= 40000; ++i) {
    if (std::abs(std::abs(plant_response(plant(), 0.01 * i)) - 1.0) >= 0.1) {
      first = 0.01 * i;
      break;
    }
  }
  EXPECT_NEAR(first, hi, 0.01);
  const double before = usable_bandwidth_hz(plant(), m, VectorXd());
  EXPECT_EQ(before, std::ceil(hi));
  // After, q = 2^24, R = 10: T G stays within 10 % of 1 beyond the plant's own limit.
  const VectorXd K = steady_gain(m, std::ldexp(1.0, 24) / 10.0);
  const double after = usable_bandwidth_hz(plant(), m, K);
  EXPECT_GT(after, before);
  for (double f = 1.0; f < after; f += 1.0) {
    EXPECT_LT(std::abs(std::abs(estimator_response(m, K, f) * plant_response(plant(), f)) - 1.0),
              0.1);
  }
  ::testing::Test::RecordProperty("bandwidth_before_hz", std::to_string(before));
  ::testing::Test::RecordProperty("bandwidth_after_q2e24_hz", std::to_string(after));
}

TEST(Compensator, AnalysedHarmonicsFollowTheBandAndTheRateLimit) {
  // 150 Hz: 10..4000 Hz holds h = 1..26; at 5 kHz the 0.45 x rate limit (2250 Hz) stops at 15.
  EXPECT_EQ(analysed_harmonics(150.0, 10.0, 4000.0, 10000.0).size(), 26u);
  const std::vector<int> h = analysed_harmonics(150.0, 300.0, 4000.0, 5000.0);
  ASSERT_EQ(h.size(), 14u);
  EXPECT_EQ(h.front(), 2);
  EXPECT_EQ(h.back(), 15);
  EXPECT_TRUE(analysed_harmonics(150.0, 10.0, 100.0, 10000.0).empty());
}

TEST(Compensator, BadInputIsNamed) {
  std::vector<SensorMode> modes = plant();
  modes[2].fn_hz = 6000.0;
  testing::expect_input_error(
      [&] { make_compensator(modes, kTpf, kFs); },
      "modes[2].fn_hz = 6000: must be > 0 and below the filter Nyquist 5000 Hz");
  modes = plant();
  modes[0].zeta = 0.0;
  testing::expect_input_error([&] { make_compensator(modes, kTpf, kFs); },
                              "modes[0].zeta = 0: must be finite and > 0");
  testing::expect_input_error([&] { make_compensator(plant(), 5000.0, kFs); },
                              "tpf_hz = 5000: must be > 0 and below the filter Nyquist 5000 Hz");
  const CompensatorModel m = make_compensator(plant(), kTpf, kFs);
  VectorXd est;
  testing::expect_input_error(
      [&] { compensate(m, 0.0, 1.0, GainMode::kTimeVarying, VectorXd::Ones(3), &est); },
      "compensate: q = 0: must be finite and > 0");
  testing::expect_input_error([&] { steady_gain(m, -1.0); },
                              "steady_gain: q_over_r = -1: must be finite and > 0");
  const std::vector<SensorMode> p = plant();
  TapSweepInput in = synthetic_taps(&p);
  in.band_hi_hz = 100.0;
  const SweepCurve c = tap_sweep(in, kRpm, kTeeth);
  EXPECT_TRUE(c.summary.failed());
  EXPECT_EQ(c.summary.message,
            "no spindle harmonic h x 150 Hz lies inside band [10, 100] Hz and at or below 0.45 x "
            "the filter rate 10000 Hz");
}

}  // namespace
}  // namespace sifs
}  // namespace chatterlab
