// The unscented filter (analysis/kalman/unscented_kalman_filter.h) against closed forms and
// against the extended filter where the two must agree.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "analysis/kalman/extended_kalman_filter.h"
#include "analysis/kalman/unscented_kalman_filter.h"

namespace chatterlab {
namespace kalman {
namespace {

// Scalar x' = x^2, no process noise; h(x) = x with variance r.
struct Square {
  static constexpr int kStates = 1;
  static constexpr int kMeasurements = 1;
  using State = Matrix<1, 1>;
  using Measurement = Matrix<1, 1>;
  using Input = int;
  State propagate(const State& x, int, Matrix<1, 1>* J) const {
    if (J) (*J)(0, 0) = 2.0 * x[0];
    return State(x[0] * x[0]);
  }
  void add_process_noise(const State&, Matrix<1, 1>*) const {}
  Measurement measure(const State& x, Matrix<1, 1>* J) const {
    if (J) (*J)(0, 0) = 1.0;
    return x;
  }
  const Matrix<1, 1>& measurement_noise() const { return R; }
  Matrix<1, 1> R = Matrix<1, 1>::Constant(0.25);
};

// A Gaussian x ~ N(mu, s^2) through x^2: mean mu^2 + s^2, variance 4 mu^2 s^2 + 2 s^4. With
// alpha = 1, beta = 2, kappa = 0 (n = 1: points mu, mu +- s; Wm = 0, 1/2, 1/2; Wc_0 = 2) the
// unscented transform gives both exactly. Tolerance 1e-14 relative: rounding of a few
// operations.
TEST(Unscented, SquareOfAGaussianHasTheExactMeanAndVariance) {
  const double mu = 1.7;
  const double s = 0.3;
  UnscentedKalmanFilter<Square> f(Square{}, Matrix<1, 1>(mu), Matrix<1, 1>(s * s));
  f.predict(0);
  EXPECT_NEAR(f.state()[0], mu * mu + s * s, 1e-14 * (mu * mu));
  EXPECT_NEAR(f.covariance()(0, 0), 4 * mu * mu * s * s + 2 * s * s * s * s,
              1e-14 * (4 * mu * mu * s * s));
  // The EKF linearizes: mean mu^2, variance 4 mu^2 s^2.
  ExtendedKalmanFilter<Square> e(Square{}, Matrix<1, 1>(mu), Matrix<1, 1>(s * s));
  e.predict(0);
  EXPECT_DOUBLE_EQ(e.state()[0], mu * mu);
  EXPECT_DOUBLE_EQ(e.covariance()(0, 0), 4 * mu * mu * s * s);
}

// A damped oscillator with a nonlinear spring (x'' = -k x - eps x^3 - c v), two states measured
// through h(x) = x + a x^2 (not a selection: the sigma-point update) or through a selection.
template <bool kSelects>
struct Duffing {
  static constexpr int kStates = 3;  // x, v, k
  static constexpr int kMeasurements = 1;
  using State = Matrix<3, 1>;
  using Measurement = Matrix<1, 1>;
  using Input = double;  // force
  double T = 1e-3;
  double quadratic = 0.0;  // a of h
  State propagate(const State& x, double u, Matrix<3, 3>* J) const {
    State y = x;
    const double acc = u - x[2] * x[0] - 50.0 * x[0] * x[0] * x[0] - 0.4 * x[1];
    y[1] = x[1] + T * acc;
    y[0] = x[0] + T * y[1];
    if (J) {
      J->setIdentity();
      const double dacc_dx = -x[2] - 150.0 * x[0] * x[0];
      (*J)(1, 0) = T * dacc_dx;
      (*J)(1, 1) = 1.0 - 0.4 * T;
      (*J)(1, 2) = -T * x[0];
      (*J)(0, 0) = 1.0 + T * (*J)(1, 0);
      (*J)(0, 1) = T * (*J)(1, 1);
      (*J)(0, 2) = T * (*J)(1, 2);
    }
    return y;
  }
  void add_process_noise(const State&, Matrix<3, 3>* P) const {
    (*P)(1, 1) += 1e-6;
    (*P)(2, 2) += 1e-8;
  }
  Measurement measure(const State& x, Matrix<1, 3>* J) const {
    if (J) *J << 1.0 + 2.0 * quadratic * x[0], 0.0, 0.0;
    return Measurement(x[0] + quadratic * x[0] * x[0]);
  }
  const Matrix<1, 1>& measurement_noise() const { return R; }
  Matrix<1, 1> R = Matrix<1, 1>::Constant(1e-6);
};
template <>
struct Duffing<true> : Duffing<false> {
  static constexpr int measured_state(int) { return 0; }
};
static_assert(SelectsStates<Duffing<true>>::value && !SelectsStates<Duffing<false>>::value);

// The same linear h read from P (selection) and passed through the sigma points: the unscented
// transform of a linear function is exact, so the two paths agree to rounding over 5,000 steps
// of a nonlinear process. Tolerance 1e-9 relative on the state and covariance.
TEST(Unscented, SelectionAndSigmaPointUpdatesAgreeForALinearMeasurement) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-3);
  const Matrix<3, 1> x0(0.1, 0.0, 30.0);
  const Matrix<3, 3> P0 = Matrix<3, 1>(1e-2, 1e-2, 25.0).asDiagonal();
  UnscentedKalmanFilter<Duffing<true>> a(Duffing<true>{}, x0, P0);
  UnscentedKalmanFilter<Duffing<false>> b(Duffing<false>{}, x0, P0);
  Duffing<false> truth;
  Matrix<3, 1> x(0.2, 0.0, 40.0);
  double nis_a = 0.0;
  double nis_b = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const double u = std::sin(0.01 * k);
    x = truth.propagate(x, u, nullptr);
    const Matrix<1, 1> z(x[0] + noise(rng));
    a.predict(u);
    b.predict(u);
    nis_a += a.update(z).nis;
    nis_b += b.update(z).nis;
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.state()[i], b.state()[i], 1e-9 * std::abs(a.state()[i]) + 1e-15) << i;
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(a.covariance()(i, j), b.covariance()(i, j),
                  1e-9 * std::sqrt(a.covariance()(i, i) * a.covariance()(j, j)))
          << i << "," << j;
    }
  }
  EXPECT_NEAR(nis_a, nis_b, 1e-9 * nis_a);
  // And the stiffness is found: 40 from a start of 30, within 1 %.
  EXPECT_NEAR(a.state()[2], 40.0, 0.4);
}

// A nonlinear measurement h(x) = x + a x^2: the filter tracks the truth and its NIS is
// chi-square(1) on average (mean over 5,000 updates within 0.8-1.2; the 95 % band of a mean of
// 5,000 chi-square(1) values is 0.96-1.04, widened for the small nonlinearity left).
TEST(Unscented, NonlinearMeasurementStaysConsistent) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 1e-3);
  Duffing<false> model;
  model.quadratic = 2.0;
  const Matrix<3, 1> x0(0.1, 0.0, 30.0);
  const Matrix<3, 3> P0 = Matrix<3, 1>(1e-2, 1e-2, 25.0).asDiagonal();
  UnscentedKalmanFilter<Duffing<false>> f(model, x0, P0);
  Matrix<3, 1> x(0.2, 0.0, 40.0);
  double nis = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const double u = std::sin(0.01 * k);
    x = model.propagate(x, u, nullptr);
    const Matrix<1, 1> z(model.measure(x, nullptr)[0] + noise(rng));
    f.predict(u);
    nis += f.update(z).nis;
  }
  EXPECT_GT(nis / 5000, 0.8);
  EXPECT_LT(nis / 5000, 1.2);
  EXPECT_NEAR(f.state()[2], 40.0, 0.4);
}

// A covariance that is not positive definite makes the estimate NaN (the caller's check).
TEST(Unscented, IndefiniteCovarianceGivesNaN) {
  Matrix<3, 3> P = Matrix<3, 3>::Identity();
  P(2, 2) = -1.0;
  UnscentedKalmanFilter<Duffing<true>> f(Duffing<true>{}, Matrix<3, 1>::Zero(), P);
  f.predict(0.0);
  EXPECT_TRUE(std::isnan(f.state()[0]));
}

TEST(Unscented, OptionsNameTheirRule) {
  const auto message = [](const UnscentedOptions& o) {
    try {
      validate(o, 5);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  UnscentedOptions o;
  EXPECT_EQ(message(o), "no error");
  o.alpha = 0.0;
  EXPECT_EQ(message(o), "ukf.alpha = 0.000000: must be > 0");
  o = UnscentedOptions{};
  o.kappa = -5.0;
  EXPECT_EQ(message(o), "ukf.kappa = -5.000000: n + kappa must be > 0 (n = 5)");
}

}  // namespace
}  // namespace kalman
}  // namespace chatterlab
