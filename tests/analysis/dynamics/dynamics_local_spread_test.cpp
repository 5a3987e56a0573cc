#include <gtest/gtest.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/dynamics/local_spread.h"

namespace chatterlab {
namespace dynamics {
namespace {

constexpr int kW = 61;  // the default window (BifurcationOptions)

// Second method for one window: the quadratic trend by Householder QR (not the normal
// equations), all points kept (no glitches in the inputs it is used on), the quartile by a full
// sort: sqrt(m / (m - 3)) q75|r| / 1.1503 with q75 interpolated at 0.75 (m - 1).
double reference_spread(const Eigen::VectorXd& x) {
  const Eigen::Index m = x.size();
  Eigen::MatrixXd basis(m, 3);
  for (Eigen::Index k = 0; k < m; ++k) {
    const double t = static_cast<double>(k) - 0.5 * static_cast<double>(m - 1);
    basis.row(k) << 1.0, t, t * t;
  }
  const Eigen::VectorXd r = x - basis * basis.householderQr().solve(x);
  std::vector<double> a(r.data(), r.data() + m);
  for (double& v : a) v = std::abs(v);
  std::sort(a.begin(), a.end());
  const double pos = 0.75 * static_cast<double>(m - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const double q =
      lo + 1 < a.size() ? a[lo] + (pos - static_cast<double>(lo)) * (a[lo + 1] - a[lo]) : a[lo];
  return std::sqrt(static_cast<double>(m) / static_cast<double>(m - 3)) * q / 1.1503493803760079;
}

Eigen::VectorXd white(Eigen::Index n, double sigma, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = g(rng);
  return x;
}

TEST(LocalSpread, WhiteNoiseGivesSigmaWithTheQuartileScaleStd) {
  // s_n estimates sigma; its relative std is 0.914 / sqrt(W) = 0.117 (asymptotic variance of the
  // upper quartile of |N|: sqrt(p (1 - p)) / (2 phi(q) q) with p = 0.75, q = 1.1503). Over 20,000
  // revolutions the mean of s_n has a std of about 0.117 / sqrt(20000 / W) = 0.65 %, and the
  // finite-window bias of an order statistic is about -1 %: 3 % tolerance. The std to 10 %.
  const double sigma = 5e-7;
  const LocalSpread ls = local_spread(white(20000, sigma, 11), kW);
  const Eigen::ArrayXd s = ls.spread.array() / sigma;
  const double mean = s.mean();
  const double sd = std::sqrt((s - mean).square().mean());
  EXPECT_NEAR(mean, 1.0, 0.03);
  EXPECT_NEAR(sd / (0.914 / std::sqrt(kW)), 1.0, 0.10);
  // Standardised central residuals have std sigma: 2 % (the std of a 20,000-sample std is 0.5 %).
  const double e_sd = std::sqrt(ls.central_residual.array().square().mean());
  EXPECT_NEAR(e_sd / sigma, 1.0, 0.02);
}

TEST(LocalSpread, SlowDriftIsRemoved) {
  // A quadratic drift leaves nothing but rounding. The 2e-7 m wander of period 1,500
  // revolutions leaves its cubic term over one window, A (2 pi / 1500)^3 (W/2)^3 / 6 = 6.6e-11 m
  // at the window's edge (measured s: 1.1e-11 m); 1e-10 m, 2e-4 of the 5e-7 m noise.
  const Eigen::Index n = 7740;
  Eigen::VectorXd line(n);
  Eigen::VectorXd curve(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u = static_cast<double>(i) / static_cast<double>(n);
    line[i] = 2e-5 + 3e-6 * u + 1e-6 * u * u;
    curve[i] = 2e-5 + 1e-6 * u * u + 2e-7 * std::sin(2 * kPi * static_cast<double>(i) / 1500);
  }
  EXPECT_LT(local_spread(line, kW).spread.maxCoeff(), 1e-18);
  EXPECT_LT(local_spread(curve, kW).spread.maxCoeff(), 1e-10);
}

TEST(LocalSpread, ChatterPatternsScaleWithAmplitude) {
  // Quasi-periodic A cos(2 pi nu n): the upper quartile of |cos| of a uniform phase is
  // cos(pi / 8), so s -> sqrt(61/58) 0.9239 A / 1.1503 = 0.824 A; over 61 phases the quartile
  // wanders (measured -4..+1 %): 5 %.
  // Alternating +-A: every window is the same pattern up to sign, so s_n is constant and equals
  // the second method's value on one window, to rounding.
  const double a = 1e-5;
  const double nu = 0.6180339887498949;
  Eigen::VectorXd ring(3000);
  Eigen::VectorXd flip(3000);
  for (Eigen::Index i = 0; i < ring.size(); ++i) {
    ring[i] = a * std::cos(2 * kPi * nu * static_cast<double>(i));
    flip[i] = i % 2 == 0 ? a : -a;
  }
  const Eigen::VectorXd s_ring = local_spread(ring, kW).spread;
  const Eigen::VectorXd s_flip = local_spread(flip, kW).spread;
  const double ring_expected = std::sqrt(61.0 / 58.0) * std::cos(kPi / 8) / 1.1503493803760079 * a;
  EXPECT_NEAR(s_ring.minCoeff() / ring_expected, 1.0, 0.05);
  EXPECT_NEAR(s_ring.maxCoeff() / ring_expected, 1.0, 0.05);
  const double flip_expected = reference_spread(flip.head(kW));
  EXPECT_NEAR(s_flip.minCoeff() / flip_expected, 1.0, 1e-9);
  EXPECT_NEAR(s_flip.maxCoeff() / flip_expected, 1.0, 1e-9);
  EXPECT_NEAR(flip_expected / a, 0.91, 0.02);  // ~A / 1.1503 x sqrt(61/58) x (1 + O(1/W))

  // Four clusters with two on the trend, (A, 0, -A, 0): half the |r| are 0, which a median would
  // report as no spread; the upper quartile sits in the other half: s ~ 0.90 A.
  Eigen::VectorXd four(3000);
  for (Eigen::Index i = 0; i < four.size(); ++i) {
    four[i] = a * std::cos(0.5 * kPi * static_cast<double>(i));
  }
  EXPECT_GT(local_spread(four, kW).spread.minCoeff(), 0.8 * a);
}

TEST(LocalSpread, IsolatedOutliersAndShortBurstsAreIgnored) {
  // One glitch of 40 sigma every 100 revolutions: the trimmed trend ignores it and the quartile
  // moves by about one rank (1 / (f(q) W) ~ 4 % of sigma). Reference: the same noise without
  // glitches; the largest s_n may rise by one or two ranks' worth: 8 %.
  const double sigma = 5e-7;
  const Eigen::VectorXd clean = white(10000, sigma, 5);
  Eigen::VectorXd x = clean;
  for (Eigen::Index i = 50; i < x.size(); i += 100) x[i] += 40 * sigma;
  const double clean_max = local_spread(clean, kW).spread.maxCoeff();
  EXPECT_NEAR(local_spread(x, kW).spread.maxCoeff() / clean_max, 1.0, 0.08);
  // A burst of 25 revolutions of chatter at 20 sigma is seen by every window holding more than
  // a quarter (15) of it, and by no window that holds none: s_n is back at noise level (below
  // the 1.5 sigma noise maximum) from W/2 revolutions beyond the burst. In the middle the
  // quartile sits among the burst's |r|, at about 10 sigma. The bifurcation criterion drops
  // such a burst by its minimum duration (dynamics_bifurcation_test).
  Eigen::VectorXd y = white(2000, sigma, 6);
  for (Eigen::Index i = 1000; i < 1025; ++i) y[i] += 1e-5 * std::cos(2.0 * static_cast<double>(i));
  const Eigen::VectorXd sy = local_spread(y, kW).spread;
  EXPECT_LT(sy.head(1000 - kW / 2).maxCoeff(), 1.5 * sigma);
  EXPECT_LT(sy.tail(2000 - 1025 - kW / 2).maxCoeff(), 1.5 * sigma);
  EXPECT_GT(sy[1012], 5 * sigma);
}

TEST(LocalSpread, DetrendedSpreadOfOneWindow) {
  // Same statistic as one window of local_spread, for odd sizes; residuals of the trend returned.
  const Eigen::VectorXd x = white(kW, 1.0, 3);
  Eigen::VectorXd r;
  const double s = detrended_spread(x, &r);
  EXPECT_NEAR(s, local_spread(x, kW).spread[kW / 2], 1e-12);
  ASSERT_EQ(r.size(), kW);
  EXPECT_NEAR(r.sum(), 0.0, 1e-12);  // least-squares residuals are orthogonal to the constant
  EXPECT_NEAR(s, reference_spread(x), 1e-12);
  // Any size, even too: the second method on a 10-value record with a glitch-free pattern.
  Eigen::VectorXd ten(10);
  ten << 1.0, 1.0, 5.0, 5.0, 2.0, -1.0, 0.5, 3.0, 4.0, 0.0;
  Eigen::VectorXd r10;
  EXPECT_NEAR(detrended_spread(ten, &r10), reference_spread(ten), 1e-12);
  EXPECT_EQ(r10.size(), 10);
}

TEST(LocalSpread, QuartileScale) {
  // (2, 0, -2, 0, 2, 0, -2, 0, 2): sorted |v| has 4 zeros then 5 twos; the quartile at
  // position 0.75 x 8 = 6 is 2, so the scale is 2 / 1.1503. (The median, at position 4, is 2
  // here too, but would be 0 with one zero more.)
  Eigen::VectorXd v(9);
  v << 2, 0, -2, 0, 2, 0, -2, 0, 2;
  EXPECT_NEAR(quartile_scale(v), 2 / 1.1503493803760079, 1e-12);
  EXPECT_THROW(
      {
        try {
          quartile_scale(Eigen::VectorXd());
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "quartile scale: no values");
          throw;
        }
      },
      InputError);
}

TEST(LocalSpread, BadInputIsNamed) {
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(100);
  EXPECT_THROW(
      {
        try {
          local_spread(x, 40);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "local spread: window_revolutions = 40: must be odd and >= 5");
          throw;
        }
      },
      InputError);
  EXPECT_THROW(
      {
        try {
          local_spread(x.head(30), 61);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(),
                       "local spread: 30 revolutions: at least window_revolutions = 61 needed");
          throw;
        }
      },
      InputError);
  Eigen::VectorXd bad = x;
  bad[7] = std::nan("");
  EXPECT_THROW(
      {
        try {
          local_spread(bad, 61);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "local spread: x[7] = nan: must be finite");
          throw;
        }
      },
      InputError);
  EXPECT_THROW(
      {
        try {
          detrended_spread(x.head(3));
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "detrended spread: 3 values: at least 4 needed");
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace dynamics
}  // namespace chatterlab
