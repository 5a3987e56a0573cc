#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/revolution_sampling.h"

namespace chatterlab {
namespace dynamics {
namespace {

constexpr double kFs = 100000.0;               // Hz, the cut-test sample rate of 000 sec. 3.1
constexpr double kOmega = 15000.0 * kPi / 30;  // rad/s at 15,000 rpm

// theta(t) = omega0 t + alpha t^2 / 2 sampled at fs: a spindle speeding up by `alpha`.
Eigen::VectorXd angle_record(Eigen::Index n, double theta0, double omega0, double alpha) {
  Eigen::VectorXd theta(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / kFs;
    theta[i] = theta0 + omega0 * t + 0.5 * alpha * t * t;
  }
  return theta;
}

TEST(RevolutionCrossings, ConstantSpeedSinusoidMatchesClosedForm) {
  // theta linear in time: the crossing instants are exact up to rounding, t_k = (theta_s +
  // 2 pi k) / omega. x = A sin(2 pi f t) at f = 900 Hz (the tool mode): linear interpolation
  // errs by at most A (2 pi f / fs)^2 / 8.
  const double amplitude = 1e-5;
  const double f = 900.0;
  const double theta_s = 1.0;
  const Eigen::VectorXd theta = angle_record(40000, 0.0, kOmega, 0.0);  // 0.4 s, 100 revs
  Eigen::VectorXd x(theta.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x[i] = amplitude * std::sin(2 * kPi * f * static_cast<double>(i) / kFs);
  }
  const RevolutionCrossings c = revolution_crossings(theta, theta_s);
  const Eigen::VectorXd xn = sample_at_crossings(c, x);

  const double interp_bound = amplitude * std::pow(2 * kPi * f / kFs, 2) / 8;
  const double position_tol = 1e-6;  // samples: rounding of theta ~ 1e-13 rad over 630 rad
  ASSERT_EQ(c.size(), 100);          // theta spans [0, 628.3): crossings at 1 + 2 pi k, k = 0..99
  for (Eigen::Index n = 0; n < c.size(); ++n) {
    EXPECT_EQ(c.revolution[n], n);
    const double t = (theta_s + 2 * kPi * static_cast<double>(n)) / kOmega;
    EXPECT_NEAR(c.sample_position[n], t * kFs, position_tol) << n;
    EXPECT_NEAR(xn[n], amplitude * std::sin(2 * kPi * f * t), interp_bound) << n;
  }
}

TEST(RevolutionCrossings, NonUniformSpeedFindsTheSameAngleEachRevolution) {
  // Speed rising 10 % per second: t_k solves theta(t) = theta_s + 2 pi k. A signal periodic in
  // the tool angle, x = B cos(theta - theta_s) + C, must read B + C at every crossing; the
  // depth, linear in time, must read its value at t_k.
  const double alpha = 0.1 * kOmega;  // rad/s^2
  const double theta0 = -2.5;
  const double theta_s = 0.7;
  const Eigen::VectorXd theta = angle_record(50000, theta0, kOmega, alpha);
  const double b = 2e-5;
  const double c0 = -3e-6;
  Eigen::VectorXd x(theta.size());
  Eigen::VectorXd depth(theta.size());
  const double depth_rate = 1e-3 / (1290 / (kOmega / (2 * kPi)));  // 1 mm per 1,290 revs, m/s
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x[i] = b * std::cos(theta[i] - theta_s) + c0;
    depth[i] = depth_rate * static_cast<double>(i) / kFs;
  }
  const RevolutionCrossings cr = revolution_crossings(theta, theta_s);
  const Eigen::VectorXd xn = sample_at_crossings(cr, x);
  const Eigen::VectorXd dn = sample_at_crossings(cr, depth);

  // Linear interpolation of theta errs by alpha dt^2 / 8 rad, i.e. alpha / (8 omega fs)
  // samples (1e-7); of x by B (omega dt)^2 / 8 = 3e-5 B.
  const double position_tol = 1e-6;
  const double x_tol = b * std::pow(kOmega * 1.2 / kFs, 2) / 8;
  const double depth_tol = depth_rate * position_tol / kFs;
  ASSERT_GT(cr.size(), 100);
  EXPECT_EQ(cr.revolution[0], 0);  // theta0 = -2.5 < 0.7: the first target is theta_s itself
  for (Eigen::Index n = 0; n < cr.size(); ++n) {
    EXPECT_EQ(cr.revolution[n], n);
    const double target = theta_s + 2 * kPi * static_cast<double>(n) - theta0;
    const double t = (-kOmega + std::sqrt(kOmega * kOmega + 2 * alpha * target)) / alpha;
    EXPECT_NEAR(cr.sample_position[n], t * kFs, position_tol) << n;
    EXPECT_NEAR(xn[n], b + c0, x_tol) << n;
    EXPECT_NEAR(dn[n], depth_rate * t, depth_tol) << n;
  }
}

TEST(RevolutionCrossings, SamplingAngleIsTakenModuloTwoPi) {
  const Eigen::VectorXd theta = angle_record(20000, 0.3, kOmega, 0.0);
  const RevolutionCrossings a = revolution_crossings(theta, 1.0);
  const RevolutionCrossings b = revolution_crossings(theta, 1.0 + 6 * kPi);
  const RevolutionCrossings c = revolution_crossings(theta, 1.0 - 4 * kPi);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  for (Eigen::Index n = 0; n < a.size(); ++n) {
    EXPECT_NEAR(b.sample_position[n], a.sample_position[n], 1e-6);
    EXPECT_NEAR(c.sample_position[n], a.sample_position[n], 1e-6);
    EXPECT_EQ(b.revolution[n], a.revolution[n] - 3);
    EXPECT_EQ(c.revolution[n], a.revolution[n] + 2);
  }
}

TEST(RevolutionCrossings, CrossingsOnTheEndSamplesAreIncluded) {
  // theta = 0, pi/2, ..., 4 pi: crossings of 0 at samples 0, 4 and 8 exactly.
  Eigen::VectorXd theta(9);
  for (Eigen::Index i = 0; i < 9; ++i) theta[i] = 0.5 * kPi * static_cast<double>(i);
  const RevolutionCrossings c = revolution_crossings(theta, 0.0);
  ASSERT_EQ(c.size(), 3);
  EXPECT_NEAR(c.sample_position[0], 0.0, 1e-12);
  EXPECT_NEAR(c.sample_position[1], 4.0, 1e-12);
  EXPECT_NEAR(c.sample_position[2], 8.0, 1e-12);
  Eigen::VectorXd s = Eigen::VectorXd::LinSpaced(9, 10.0, 18.0);
  const Eigen::VectorXd v = sample_at_crossings(c, s);
  EXPECT_DOUBLE_EQ(v[0], 10.0);
  EXPECT_DOUBLE_EQ(v[1], 14.0);
  EXPECT_DOUBLE_EQ(v[2], 18.0);
  // Less than a revolution with no target inside: nothing; an empty record: nothing.
  Eigen::VectorXd short_theta(2);
  short_theta << 0.1, 0.2;
  EXPECT_EQ(revolution_crossings(short_theta, 0.0).size(), 0);
  EXPECT_EQ(revolution_crossings(Eigen::VectorXd(), 0.0).size(), 0);
}

TEST(RevolutionCrossings, BadInputIsNamed) {
  Eigen::VectorXd theta(4);
  theta << 0.0, 1.0, 1.0, 2.0;
  EXPECT_THROW(
      {
        try {
          revolution_crossings(theta, 0.0);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(),
                       "theta[2] = 1 rad: must be above theta[1] = 1 (unwrapped, strictly "
                       "increasing)");
          throw;
        }
      },
      InputError);
  theta << 0.0, 1.0, std::nan(""), 2.0;
  EXPECT_THROW(
      {
        try {
          revolution_crossings(theta, 0.0);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "theta[2] = nan rad: must be finite");
          throw;
        }
      },
      InputError);
  theta << 0.0, 1.0, 2.0, 7.0;
  EXPECT_THROW(revolution_crossings(theta, INFINITY), InputError);
  const RevolutionCrossings c = revolution_crossings(theta, 0.5);
  EXPECT_THROW(
      {
        try {
          sample_at_crossings(c, Eigen::VectorXd::Zero(3));
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(),
                       "once-per-revolution sampling: signal has 3 samples, the angle record 4: "
                       "must be equal");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
