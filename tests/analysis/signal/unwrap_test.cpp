// Phase unwrapping against phases whose unwrapped values are known in closed form.
#include "analysis/signal/unwrap.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace signal {
namespace {

// fmod of values up to ~60 rad rounds to a few ulps of 60 (1e-14); the sum of added turns is
// exact to the same order.
constexpr double kRoundingRad = 1e-12;

Eigen::VectorXd wrapped(const Eigen::VectorXd& phase) {
  Eigen::VectorXd w(phase.size());
  for (Eigen::Index i = 0; i < phase.size(); ++i) {
    w[i] = std::fmod(phase[i], kTwoPi);
    if (w[i] < 0) w[i] += kTwoPi;
  }
  return w;
}

TEST(Unwrap, IncreasingPhaseComesBackWhole) {
  // theta_1 at 400 samples per revolution over 10 revolutions, starting at 0.3 rad.
  const Eigen::Index n = 4000;
  const Eigen::VectorXd truth = Eigen::VectorXd::LinSpaced(n, 0.3, 0.3 + kTwoPi * (n - 1) / 400.0);
  const Eigen::VectorXd u = unwrap_phase_rad(wrapped(truth));
  ASSERT_EQ(u.size(), n);
  EXPECT_LT((u - truth).cwiseAbs().maxCoeff(), kRoundingRad);
}

TEST(Unwrap, DecreasingPhaseLosesTurns) {
  // Turning backwards by 0.9 rad per sample (less than half a turn): the unwrapped phase
  // follows it below zero.
  const Eigen::Index n = 50;
  const Eigen::VectorXd truth = Eigen::VectorXd::LinSpaced(n, 6.0, 6.0 - 0.9 * (n - 1));
  const Eigen::VectorXd u = unwrap_phase_rad(wrapped(truth));
  EXPECT_LT((u - truth).cwiseAbs().maxCoeff(), kRoundingRad);
}

TEST(Unwrap, StepsOfLessThanHalfATurnAreKept) {
  // No jump exceeds pi: nothing is added (exact).
  Eigen::VectorXd p(5);
  p << 0.0, 3.0, 0.5, -2.0, 1.0;
  EXPECT_EQ(unwrap_phase_rad(p), p);
}

TEST(Unwrap, ShortInputsComeBackUnchanged) {
  EXPECT_EQ(unwrap_phase_rad(Eigen::VectorXd()).size(), 0);
  const Eigen::VectorXd one = Eigen::VectorXd::Constant(1, 5.0);
  EXPECT_EQ(unwrap_phase_rad(one), one);
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
