#include "analysis/signal/pulses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace signal {
namespace {

// A pulse train with linear ramps: the 50 % level of rising ramp k is at sample edge[k].
// A ramp spanning >= 2 samples makes linear interpolation at mid-level exact.
Eigen::VectorXd ramp_train(Eigen::Index n, const std::vector<double>& edges, double rise,
                           double width, double amplitude) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (double e : edges) {
      const double tau = static_cast<double>(i) - e;
      double v = 0.0;
      if (tau > -0.5 * rise && tau < 0.5 * rise) v = (tau + 0.5 * rise) / rise;
      if (tau >= 0.5 * rise && tau <= 0.5 * rise + width) v = 1.0;
      if (tau > 0.5 * rise + width && tau < 1.5 * rise + width) {
        v = 1.0 - (tau - 0.5 * rise - width) / rise;
      }
      x[i] += amplitude * v;
    }
  }
  return x;
}

// Linear interpolation of a straight ramp is exact up to rounding.
constexpr double kExactTol = 1e-9;

TEST(RisingEdges, RecoversFractionalEdgesOfRampedPulses) {
  const std::vector<double> truth = {10.3, 117.77, 240.5, 333.01};
  const Eigen::VectorXd x = ramp_train(400, truth, 3.0, 20.0, 5.0);
  const std::vector<double> e = rising_edges(x, 2.5, 0.5);
  ASSERT_EQ(e.size(), truth.size());
  for (std::size_t k = 0; k < truth.size(); ++k) EXPECT_NEAR(e[k], truth[k], kExactTol) << k;
}

TEST(RisingEdges, SampledStepIsHalfWayBetweenSamples) {
  // 0 0 0 5 5 0: the 2.5 V crossing is at 2.5 by interpolation (a step gives no sub-sample
  // information, hence the +-0.5 sample quantisation documented for steps).
  Eigen::VectorXd x(6);
  x << 0, 0, 0, 5, 5, 0;
  const std::vector<double> e = rising_edges(x, 2.5, 0.5);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0], 2.5, kExactTol);
}

TEST(RisingEdges, HysteresisSuppressesChatterAroundThreshold) {
  // Hand-built: rises to 3, dips to 2.4 (above 2.5 - 0.5), rises again, then falls to 0.
  Eigen::VectorXd x(10);
  x << 0, 3, 2.4, 3, 2.4, 3, 0, 0, 4, 0;
  const std::vector<double> with = rising_edges(x, 2.5, 0.5);
  ASSERT_EQ(with.size(), 2u);
  EXPECT_NEAR(with[0], 0.0 + 2.5 / 3.0, kExactTol);
  EXPECT_NEAR(with[1], 7.0 + 2.5 / 4.0, kExactTol);
  // Without hysteresis each dip below 2.5 re-arms: 4 edges.
  EXPECT_EQ(rising_edges(x, 2.5, 0.0).size(), 4u);
}

TEST(RisingEdges, StartingHighOrInDeadBandIsNotAnEdge) {
  Eigen::VectorXd high(5);
  high << 5, 5, 0, 5, 5;
  std::vector<double> e = rising_edges(high, 2.5, 0.5);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0], 2.5, kExactTol);
  Eigen::VectorXd dead_band(4);  // starts at 2.2 V: never below 2.0 V, never armed
  dead_band << 2.2, 5, 5, 5;
  EXPECT_TRUE(rising_edges(dead_band, 2.5, 0.5).empty());
  EXPECT_TRUE(rising_edges(Eigen::VectorXd(), 2.5, 0.5).empty());
}

TEST(RisingEdges, NaNSamplesAreSkipped) {
  Eigen::VectorXd x(5);
  x << 0, 1, std::nan(""), 4, 4;  // interpolate from sample 1 (1 V) to sample 3 (4 V)
  const std::vector<double> e = rising_edges(x, 2.5, 0.5);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0], 1.0 + 2.0 * (1.5 / 3.0), kExactTol);
}

TEST(RisingEdges, NoisyPulseTrainGivesOneEdgePerPulse) {
  // 40 pulses with 4-sample ramps every 97.3 samples, 0.2 V noise (seeded). With 0.5 V
  // hysteresis (2.5 sigma) no double edges; the interpolation error is about
  // sigma / slope = 0.2 V / (5 V / 4 samples) = 0.16 sample, so 0.8 sample is 5 sigma.
  constexpr double kNoisyTol = 0.8;
  std::vector<double> truth;
  for (int k = 0; k < 40; ++k) truth.push_back(20.0 + 97.3 * k);
  Eigen::VectorXd x = ramp_train(4000, truth, 4.0, 25.0, 5.0);
  std::mt19937_64 rng(42);
  std::normal_distribution<double> noise(0.0, 0.2);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += noise(rng);
  const std::vector<double> e = rising_edges(x, 2.5, 0.5);
  ASSERT_EQ(e.size(), truth.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    worst = std::max(worst, std::abs(e[k] - truth[k]));
  }
  EXPECT_LT(worst, kNoisyTol);
}

TEST(RisingEdges, RejectsBadArguments) {
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  try {
    rising_edges(x, 2.5, -0.1);
    FAIL() << "expected InputError";
  } catch (const InputError& err) {
    EXPECT_STREQ(err.what(), "rising_edges.hysteresis = -0.1: must be finite and >= 0");
  }
  try {
    rising_edges(x, std::nan(""), 0.5);
    FAIL() << "expected InputError";
  } catch (const InputError& err) {
    EXPECT_STREQ(err.what(), "rising_edges.threshold = nan: must be finite");
  }
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
