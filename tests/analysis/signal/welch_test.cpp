// Welch cross-spectra (analysis/signal/welch.h).
#include "analysis/signal/welch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace signal {
namespace {

Eigen::VectorXd white(Eigen::Index n, std::uint64_t seed, double sigma = 1.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, sigma);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = nd(rng);
  return x;
}

// x[k] = 0.5 r[k] + 0.3 r[k-1] - 0.2 r[k-2]: H1 = S_rx / S_rr is the filter's FRF
// H(f) = 0.5 + 0.3 z^-1 - 0.2 z^-2, z = exp(j 2 pi f / fs) (reference; tolerance 1 % of |H|:
// the leakage of a 3-tap filter through a 512-sample Hann window, and the variance of 390
// segments), and the coherence is 1 within 1e-3 where |H| > 0.2 (the filter's two-sample memory
// crosses each segment's edges; that leakage is relative to |H|, which is 0 at 500 Hz).
TEST(Welch, H1OfAFilterAndItsPhaseConvention) {
  const double fs = 1000.0;
  const Eigen::VectorXd r = white(100000, 1);
  Eigen::VectorXd x(r.size());
  for (Eigen::Index k = 0; k < r.size(); ++k) {
    x[k] = 0.5 * r[k] + (k >= 1 ? 0.3 * r[k - 1] : 0.0) - (k >= 2 ? 0.2 * r[k - 2] : 0.0);
  }
  const CrossSpectra s = welch_cross_spectra(r, {x}, 512, fs);
  EXPECT_EQ(s.segments, (100000 - 512) / 256 + 1);
  ASSERT_EQ(s.f_hz.size(), 257);
  EXPECT_DOUBLE_EQ(s.f_hz[256], 500.0);
  for (Eigen::Index k = 1; k < 256; k += 5) {
    const std::complex<double> z = std::polar(1.0, kTwoPi * s.f_hz[k] / fs);
    const std::complex<double> H = 0.5 + 0.3 / z - 0.2 / (z * z);
    const std::complex<double> H1 = s.S_rx[0][k] / s.S_rr[k];
    EXPECT_LT(std::abs(H1 - H), 0.01 * std::abs(H)) << s.f_hz[k];
    const double coh = std::norm(s.S_rx[0][k]) / (s.S_rr[k] * s.S_xx[0][k]);
    if (std::abs(H) > 0.2) {
      EXPECT_NEAR(coh, 1.0, 1e-3) << s.f_hz[k];
    }
  }
}

// White noise of variance 4 at fs = 2000: the one-sided density is 2 sigma^2 / fs = 0.004 per
// Hz; its integral is the variance (tolerance 2 %: 780 segments).
TEST(Welch, DensityScalingIntegratesToTheVariance) {
  const double fs = 2000.0;
  const Eigen::VectorXd r = white(200000, 2, 2.0);
  const CrossSpectra s = welch_cross_spectra(r, {}, 512, fs);
  const double df = fs / 512;
  EXPECT_NEAR(s.S_rr.sum() * df, 4.0, 0.08);
  EXPECT_NEAR(s.S_rr.segment(10, 200).mean(), 2.0 * 4.0 / fs, 0.03 * 2.0 * 4.0 / fs);
}

// Uncorrelated noise of the same variance on the output halves the coherence: gamma^2 =
// 1 / (1 + 1) = 0.5 (tolerance 0.05: the coherence estimate's spread over 780 segments).
TEST(Welch, CoherenceFallsWithOutputNoise) {
  const Eigen::VectorXd r = white(200000, 3);
  const Eigen::VectorXd x = r + white(200000, 4);
  const CrossSpectra s = welch_cross_spectra(r, {x}, 512, 1000.0);
  for (Eigen::Index k = 5; k < 250; k += 20) {
    EXPECT_NEAR(std::norm(s.S_rx[0][k]) / (s.S_rr[k] * s.S_xx[0][k]), 0.5, 0.05);
  }
}

TEST(Welch, BadSegmentsAreInputErrors) {
  const Eigen::VectorXd r = white(100, 5);
  EXPECT_THROW(welch_cross_spectra(r, {}, 7, 1000.0), InputError);
  EXPECT_THROW(welch_cross_spectra(r, {}, 128, 1000.0), InputError);
  EXPECT_THROW(welch_cross_spectra(r, {Eigen::VectorXd::Zero(99)}, 64, 1000.0), InputError);
  EXPECT_THROW(welch_cross_spectra(r, {}, 64, 0.0), InputError);
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
