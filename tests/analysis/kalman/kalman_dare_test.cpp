// The steady-state Kalman filter (analysis/kalman/dare.h) against closed forms, a printed
// MATLAB value, the Riccati difference equation iterated to convergence, and the time-varying
// KalmanFilter run to steady state.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <functional>
#include <random>
#include <string>

#include "analysis/common/summary.h"
#include "analysis/kalman/dare.h"
#include "analysis/kalman/kalman_filter.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab {
namespace kalman {
namespace {

using Eigen::MatrixXd;

// One step of the filter's Riccati difference equation for the prior covariance (the second
// method, written out here from the DARE's definition in dare.h):
//   P' = A P A^T - A P C^T (C P C^T + R)^-1 C P A^T + Q.
MatrixXd riccati_step(const MatrixXd& A, const MatrixXd& C, const MatrixXd& Q, const MatrixXd& R,
                      const MatrixXd& P) {
  const MatrixXd APCt = A * P * C.transpose();
  const MatrixXd S = C * P * C.transpose() + R;
  const MatrixXd next = A * P * A.transpose() - APCt * S.inverse() * APCt.transpose() + Q;
  return 0.5 * (next + next.transpose());
}

// Iterates from P = Q until the step changes P by less than 1e-15 of |P| (or 100000 steps).
MatrixXd riccati_limit(const MatrixXd& A, const MatrixXd& C, const MatrixXd& Q, const MatrixXd& R) {
  MatrixXd P = Q;
  for (int k = 0; k < 100000; ++k) {
    const MatrixXd next = riccati_step(A, C, Q, R, P);
    const double change = (next - P).norm();
    P = next;
    if (change <= 1e-15 * P.norm()) break;
  }
  return P;
}

double relative_error(const MatrixXd& X, const MatrixXd& ref) {
  return (X - ref).norm() / ref.norm();
}

// Scalar DARE p = a^2 p - a^2 c^2 p^2 / (c^2 p + r) + q, i.e.
// c^2 p^2 + (r (1 - a^2) - q c^2) p - q r = 0, positive root.
double scalar_dare(double a, double c, double q, double r) {
  const double b = r * (1.0 - a * a) - q * c * c;
  return (-b + std::sqrt(b * b + 4.0 * c * c * q * r)) / (2.0 * c * c);
}

TEST(SteadyStateGain, ScalarMatchesTheQuadraticRoot) {
  // Stable, random-walk and unstable a; the closed form's rounding is ~1e-16, the solver's
  // convergence test 1e-13: tolerance 1e-12 relative.
  constexpr double kTolerance = 1e-12;
  struct Case {
    double a, c, q, r;
  };
  for (const Case& k : {Case{0.9, 1.0, 0.1, 1.0}, Case{1.0, 2.0, 1e-3, 0.5},
                        Case{1.5, 0.3, 2.0, 4.0}, Case{-0.2, 1.0, 1e4, 1e-4}}) {
    const SteadyStateKalman s =
        steady_state_gain(MatrixXd::Constant(1, 1, k.a), MatrixXd::Constant(1, 1, k.c),
                          MatrixXd::Constant(1, 1, k.q), MatrixXd::Constant(1, 1, k.r));
    ASSERT_TRUE(s.summary.ok()) << s.summary.message;
    const double p = scalar_dare(k.a, k.c, k.q, k.r);
    EXPECT_NEAR(s.P(0, 0), p, kTolerance * p) << "a = " << k.a;
    const double gain = p * k.c / (k.c * k.c * p + k.r);
    EXPECT_NEAR(s.K(0, 0), gain, kTolerance * std::abs(gain));
    EXPECT_NEAR(s.L(0, 0), k.a * gain, kTolerance * std::abs(k.a * gain) + 1e-300);
    EXPECT_NEAR(s.P_posterior(0, 0), p - gain * gain * (k.c * k.c * p + k.r), kTolerance * p);
    EXPECT_LT(s.residual, 1e-14);
    EXPECT_NEAR(s.spectral_radius, std::abs(k.a * (1.0 - gain * k.c)), 1e-12);
  }
}

TEST(SteadyStateGain, CoupledCaseFromADecoupledOne) {
  // Closed form for a fully coupled system: the DARE is covariant under x' = T x (A' = T A T^-1,
  // C' = C T^-1, Q' = T Q T^T give P' = T P T^T, K' = T K). Start from two decoupled scalar
  // problems (an unstable and a stable mode, both measured) and a non-orthogonal T.
  MatrixXd A0 = MatrixXd::Zero(2, 2), Q0 = MatrixXd::Zero(2, 2), R(2, 2);
  A0.diagonal() << 1.2, 0.6;
  Q0.diagonal() << 0.3, 2.0;
  R << 0.5, 0.0, 0.0, 0.2;
  MatrixXd T(2, 2);
  T << 1.0, 0.4, -0.7, 2.0;
  const MatrixXd Ti = T.inverse();
  const MatrixXd A = T * A0 * Ti, C = Ti, Q = T * Q0 * T.transpose();
  MatrixXd P0 = MatrixXd::Zero(2, 2);
  P0(0, 0) = scalar_dare(1.2, 1.0, 0.3, 0.5);
  P0(1, 1) = scalar_dare(0.6, 1.0, 2.0, 0.2);
  const MatrixXd P_exact = T * P0 * T.transpose();
  const SteadyStateKalman s = steady_state_gain(A, C, 0.5 * (Q + Q.transpose()), R);
  ASSERT_TRUE(s.summary.ok()) << s.summary.message;
  // 1e-12: T's condition number (~3) times the scalar case's tolerance.
  EXPECT_LT(relative_error(s.P, P_exact), 1e-12);
  MatrixXd K0 = MatrixXd::Zero(2, 2);
  K0(0, 0) = P0(0, 0) / (P0(0, 0) + 0.5);
  K0(1, 1) = P0(1, 1) / (P0(1, 1) + 0.2);
  EXPECT_LT(relative_error(s.K, T * K0), 1e-12);
}

TEST(SteadyStateGain, MatchesMatlabIdareExample) {
  // MATLAB Control System Toolbox, idare documentation, "Solve Discrete-Time Algebraic Riccati
  // Equation": A = [-0.9 -0.3; 0.7 0.1], B = [1; 1], Q = [1 0; 0 3], R = 0.1 gives
  // X = [4.7687 0.9438; 0.9438 3.2369] (printed to 4 decimals). The control DARE in (A, B) is
  // the filter DARE in (A^T, B^T). Tolerance: half a unit of the last printed digit.
  MatrixXd A(2, 2), B(2, 1), Q(2, 2);
  A << -0.9, -0.3, 0.7, 0.1;
  B << 1.0, 1.0;
  Q << 1.0, 0.0, 0.0, 3.0;
  const SteadyStateKalman s =
      steady_state_gain(A.transpose(), B.transpose(), Q, MatrixXd::Constant(1, 1, 0.1));
  ASSERT_TRUE(s.summary.ok()) << s.summary.message;
  MatrixXd X(2, 2);
  X << 4.7687, 0.9438, 0.9438, 3.2369;
  EXPECT_LT((s.P - X).cwiseAbs().maxCoeff(), 0.5e-4);
  EXPECT_LT(s.residual, 1e-14);
}

TEST(SteadyStateGain, MatchesTheIteratedRiccatiEquation) {
  // Random 4-state, 2-output systems with one mode outside the unit circle, and a nilpotent
  // (singular) A, against riccati_limit. Tolerance 1e-10 relative: the iteration stops at a
  // change of 1e-15 |P| per step, and contracts by rho^2 per step, so its own error is
  // <= 1e-15 / (1 - rho^2), rho <= 0.97 here (checked below).
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    MatrixXd A(4, 4), C(2, 4), G(4, 4), V(2, 2);
    for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = n(rng);
    for (Eigen::Index i = 0; i < C.size(); ++i) C.data()[i] = n(rng);
    for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = n(rng);
    for (Eigen::Index i = 0; i < V.size(); ++i) V.data()[i] = n(rng);
    const Eigen::EigenSolver<MatrixXd> eig(A, false);
    A *= 1.05 / eig.eigenvalues().cwiseAbs().maxCoeff();  // spectral radius 1.05
    const MatrixXd Q = 0.1 * G * G.transpose();
    const MatrixXd R = V * V.transpose() + 0.1 * MatrixXd::Identity(2, 2);
    const SteadyStateKalman s = steady_state_gain(A, C, Q, R);
    ASSERT_TRUE(s.summary.ok()) << s.summary.message;
    ASSERT_LT(s.spectral_radius, 0.97);
    EXPECT_LT(relative_error(s.P, riccati_limit(A, C, Q, R)), 1e-10) << "trial " << trial;
    EXPECT_LT(s.residual, 1e-12);
  }
  MatrixXd A(2, 2), C(1, 2);
  A << 0.0, 1.0, 0.0, 0.0;  // nilpotent: no inverse of A exists
  C << 1.0, 0.0;
  const MatrixXd Q = MatrixXd::Identity(2, 2);
  const SteadyStateKalman s = steady_state_gain(A, C, Q, MatrixXd::Identity(1, 1));
  ASSERT_TRUE(s.summary.ok()) << s.summary.message;
  EXPECT_LT(relative_error(s.P, riccati_limit(A, C, Q, MatrixXd::Identity(1, 1))), 1e-12);
}

TEST(SteadyStateGain, IsWhereTheTimeVaryingFilterSettles) {
  // The KalmanFilter's prior covariance after many steps (from P0 = I) is the DARE's P, its
  // posterior covariance P+. The MATLAB example's system as a filter; the closed loop contracts
  // by ~0.45 per step, so 200 steps leave nothing of P0. Tolerance 1e-12 relative (rounding).
  LinearModel<2, 0, 1> m;
  m.A << -0.9, 0.7, -0.3, 0.1;
  m.C << 1.0, 1.0;
  m.Q << 1.0, 0.0, 0.0, 3.0;
  m.R << 0.1;
  const SteadyStateKalman s = steady_state_gain(m.A, m.C, m.Q, m.R);
  ASSERT_TRUE(s.summary.ok()) << s.summary.message;
  KalmanFilter<2, 0, 1> f(m, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  for (int k = 0; k < 200; ++k) {
    f.predict(Matrix<0, 1>());
    f.update(Matrix<1, 1>::Zero());
  }
  EXPECT_LT(relative_error(f.covariance(), s.P_posterior), 1e-12);
  f.predict(Matrix<0, 1>());
  EXPECT_LT(relative_error(f.covariance(), s.P), 1e-12);
}

TEST(SteadyStateGain, ReportsANonStabilizingSolution) {
  // An unstable mode without process noise: P = 0 solves the DARE (the doubling iteration starts
  // at H_0 = Q = 0 and stays there) but leaves A - L C unstable; the stabilizing solution
  // needs (A, Q^1/2) stabilizable. A failed summary, not a wrong gain.
  MatrixXd A = MatrixXd::Zero(2, 2);
  A.diagonal() << 2.0, 0.5;
  MatrixXd C(1, 2);
  C << 1.0, 1.0;
  const SteadyStateKalman s =
      steady_state_gain(A, C, MatrixXd::Zero(2, 2), MatrixXd::Identity(1, 1));
  EXPECT_FALSE(s.summary.ok());
  EXPECT_NE(s.summary.message.find("not stabilizing (spectral radius of A - L C = 2 >= 1)"),
            std::string::npos)
      << s.summary.message;
  // An unstable mode the measurement cannot see: (A, C) not detectable.
  MatrixXd C2(1, 2);
  C2 << 0.0, 1.0;
  const SteadyStateKalman u =
      steady_state_gain(A, C2, MatrixXd::Identity(2, 2), MatrixXd::Identity(1, 1));
  EXPECT_FALSE(u.summary.ok());
  EXPECT_NE(u.summary.message.find("(A, C) not detectable"), std::string::npos)
      << u.summary.message;
}

TEST(SteadyStateGain, RejectsBadInput) {
  const MatrixXd I2 = MatrixXd::Identity(2, 2), I1 = MatrixXd::Identity(1, 1);
  const MatrixXd C = MatrixXd::Ones(1, 2);
  chatterlab::testing::expect_input_error(
      [&] { steady_state_gain(MatrixXd::Ones(2, 3), C, I2, I1); },
      "dare: A size = 2 x 3: must be square, N >= 1");
  chatterlab::testing::expect_input_error(
      [&] { steady_state_gain(I2, MatrixXd::Ones(1, 3), I2, I1); },
      "dare: C size = 1 x 3: must be M x 2, M >= 1");
  chatterlab::testing::expect_input_error([&] { steady_state_gain(I2, C, I1, I1); },
                                          "dare: Q size = 1 x 1: must be 2 x 2");
  chatterlab::testing::expect_input_error([&] { steady_state_gain(I2, C, I2, I2); },
                                          "dare: R size = 2 x 2: must be 1 x 1");
  MatrixXd Q = I2;
  Q(0, 1) = 0.5;
  chatterlab::testing::expect_input_error(
      [&] { steady_state_gain(I2, C, Q, I1); },
      "dare: Q = asymmetric or non-finite: must be finite and symmetric");
  chatterlab::testing::expect_input_error(
      [&] { steady_state_gain(I2, C, -I2, I1); },
      "dare: Q smallest eigenvalue = -1: must be >= 0 (Q positive semi-definite)");
  chatterlab::testing::expect_input_error(
      [&] { steady_state_gain(I2, C, I2, -I1); },
      "dare: R smallest eigenvalue = -1: must be > 0 (R positive definite)");
  DareOptions o;
  o.max_iterations = 0;
  chatterlab::testing::expect_input_error([&] { steady_state_gain(I2, C, I2, I1, o); },
                                          "dare.max_iterations = 0: must be >= 1");
}

}  // namespace
}  // namespace kalman
}  // namespace chatterlab
