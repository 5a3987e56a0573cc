// ZOH discretization of the dynamometer model (004 eqs 2.2-2.3 with E1).
#include "analysis/forcerec/model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chatterlab {
namespace forcerec {
namespace {

// G(s) = gain / (s + p): a model whose zero-order hold is known in closed form.
ContinuousModel first_order(double p, double gain) {
  ContinuousModel m;
  m.A = Eigen::MatrixXd::Constant(1, 1, -p);
  m.B = Eigen::VectorXd::Constant(1, gain);
  m.C = Eigen::RowVectorXd::Constant(1, 1.0);
  return m;
}

TEST(ForcerecZoh, FirstOrderMatchesTheClosedForm) {
  // x' = -p x + g F: Ad = e^(-p dt), Bd = g (1 - e^(-p dt)) / p (the integral of 004 E1).
  const double p = 3000.0, g = 5.0, fs = 10240.0, dt = 1.0 / fs;
  const DiscreteModel d = zoh(first_order(p, g), fs);
  constexpr double kRel = 1e-13;  // rounding of one 2 x 2 matrix exponential
  EXPECT_NEAR(d.Ad(0, 0), std::exp(-p * dt), kRel);
  EXPECT_NEAR(d.Bd[0], g * (1.0 - std::exp(-p * dt)) / p, kRel * g / p);
}

TEST(ForcerecZoh, SampledResponseOfAHeldStepSettlesToTheDcGain) {
  // A lightly damped 1411.8 Hz mode (004 Table 3.1's x axis peak) with unit DC gain.
  const double wn = 2 * M_PI * 1411.8, zeta = 0.0214;
  ContinuousModel m;
  m.A.resize(2, 2);
  m.A << 0, 1, -wn * wn, -2 * zeta * wn;
  m.B = Eigen::Vector2d(0, wn * wn);
  m.C = Eigen::RowVector2d(1, 0);
  const DiscreteModel d = zoh(m, 10240.0);
  const Eigen::VectorXd y = simulate(d, Eigen::VectorXd::Ones(40000));
  EXPECT_NEAR(y[y.size() - 1], 1.0, 1e-9);  // held step, after 3.9 s (decay time 5 ms)
  EXPECT_EQ(y[0], 0.0);                     // the force of interval 0 shows in y(1)
  const Eigen::VectorXd h = impulse_response(d, 3);
  EXPECT_NEAR(h[0], y[1], 1e-15);
  // The sampled FRF at low frequency tends to the continuous one.
  Eigen::VectorXd f(1);
  f << 10.0;
  const std::complex<double> gc = frequency_response(m, f)[0];
  const std::complex<double> gd = frequency_response(d, f)[0];
  // ZOH delays by half a sample: gd ~ gc e^(-j pi f / fs) (1e-4 relative at 10 Hz).
  EXPECT_LT(std::abs(gd - gc * std::polar(1.0, -M_PI * 10.0 / 10240.0)), 1e-4);
}

TEST(ForcerecZoh, RefusesBadShapesAndRates) {
  ContinuousModel m = first_order(1.0, 1.0);
  EXPECT_THROW(zoh(m, 0.0), std::invalid_argument);
  EXPECT_THROW(zoh(m, std::nan("")), std::invalid_argument);
  m.B = Eigen::VectorXd::Ones(2);
  EXPECT_THROW(zoh(m, 1000.0), std::invalid_argument);
}

}  // namespace
}  // namespace forcerec
}  // namespace chatterlab
