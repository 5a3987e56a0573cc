#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/noise_level.h"

namespace chatterlab {
namespace dynamics {
namespace {

TEST(WhiteNoiseSigma, RecoversNoiseOnAChatteringDeflection) {
  // 1 s at 100 kHz of a 900 Hz, 1e-4 m deflection (the largest chatter of interest) plus a
  // 250 Hz once-per-revolution orbit, with the 5e-7 m noise of 000 sec. 6.1. The median of
  // 1e5 second differences has a relative std of 1.166 / sqrt(1e5) = 0.4 %; the deflection
  // adds (2 pi 900 / 1e5)^2 1e-4 = 3.2e-7 m of roughly sinusoidal d, which lifts the median of
  // |d| by about 3 % (measured 2.6 %). Tolerance: 5 %.
  const double sigma = 5e-7;
  const double fs = 1e5;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::VectorXd x(100000);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / fs;
    x[i] = 1e-4 * std::sin(2 * kPi * 900 * t) + 2e-5 * std::cos(2 * kPi * 250 * t) + noise(rng);
  }
  EXPECT_NEAR(white_noise_sigma(x) / sigma, 1.0, 0.05);
  // Without the deflection the estimate is unbiased. Second differences of white noise are
  // correlated (lag-1 correlation -2/3), which raises the estimate's relative std above the
  // 0.37 % of independent samples; 2 % tolerance.
  Eigen::VectorXd pure(100000);
  for (Eigen::Index i = 0; i < pure.size(); ++i) pure[i] = noise(rng);
  EXPECT_NEAR(white_noise_sigma(pure) / sigma, 1.0, 0.02);
}

TEST(WhiteNoiseSigma, BadInputIsNamed) {
  EXPECT_THROW(
      {
        try {
          white_noise_sigma(Eigen::VectorXd::Zero(2));
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "noise level: signal has 2 samples: at least 3 needed");
          throw;
        }
      },
      InputError);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(5);
  x[3] = INFINITY;
  EXPECT_THROW(
      {
        try {
          white_noise_sigma(x);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "noise level: sample 3 = inf: must be finite");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
