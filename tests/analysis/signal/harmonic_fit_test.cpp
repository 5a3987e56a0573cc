// Harmonic least-squares fit (003 eq. 3-6 as corrected by notes/003.md) against signals built
// from known c0 and c_h.
#include "analysis/signal/harmonic_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <random>

#include "analysis/common/constants.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace signal {
namespace {

using chatterlab::testing::expect_input_error;
using cd = std::complex<double>;

// Noise-free fits are exact but for rounding of sums over ~1e3..1e4 samples of O(10) values.
constexpr double kRoundingN = 1e-10;
// With white noise of standard deviation sigma over N samples each of Re c_h, Im c_h has standard
// deviation sigma sqrt(2 / N) (c0: sigma / sqrt(N)); tolerances are 5 of those.
constexpr double kNoiseSigmas = 5.0;

struct Term {
  int h;
  double amp;
  double phase_rad;
};

// c0 + sum amp cos(h Omega t + phase) at t = k / fs, plus N(0, sigma) from a seeded generator.
Eigen::VectorXd synth(Eigen::Index n, double fs, double f0, double c0,
                      const std::vector<Term>& terms, double sigma, std::uint64_t seed,
                      Eigen::VectorXd* noise = nullptr) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  Eigen::VectorXd x(n), e(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / fs;
    x[k] = c0;
    for (const Term& term : terms)
      x[k] += term.amp * std::cos(term.h * kTwoPi * f0 * t + term.phase_rad);
    e[k] = sigma > 0.0 ? normal(rng) : 0.0;
    x[k] += e[k];
  }
  if (noise) *noise = e;
  return x;
}

std::vector<int> orders(const std::vector<Term>& terms) {
  std::vector<int> h;
  for (const Term& t : terms) h.push_back(t.h);
  return h;
}

// Unbalance-like terms at 9000 rpm (format truth example: 6.7 N at 77.5 deg).
const std::vector<Term> kTerms = {
    {1, 6.7, 77.5 * kDegToRad}, {2, 2.3, -120.0 * kDegToRad}, {5, 0.9, 10.0 * kDegToRad}};

TEST(HarmonicFit, RecoversOffsetAndHarmonicsFromNoisySignal) {
  const double fs = 10000.0, f0 = 150.0, c0 = -12.0, sigma = 0.5;
  const Eigen::VectorXd x = synth(30000, fs, f0, c0, kTerms, sigma, 31);
  // 9990 samples: 149.85 revolutions, not whole, so the least-squares branch runs.
  const Eigen::Index begin = 5003, end = 14993;
  const HarmonicFit fit = fit_harmonics(x, fs, begin, end, f0, orders(kTerms));
  ASSERT_TRUE(fit.summary.ok()) << fit.summary.message;
  const double n = static_cast<double>(end - begin);
  const double tol_c0 = kNoiseSigmas * sigma / std::sqrt(n);
  const double tol_c = kNoiseSigmas * sigma * std::sqrt(2.0 / n);
  EXPECT_EQ(fit.samples, end - begin);
  EXPECT_NEAR(fit.c0, c0, tol_c0);
  double worst = 0.0;
  for (std::size_t i = 0; i < kTerms.size(); ++i) {
    const cd truth = std::polar(kTerms[i].amp, kTerms[i].phase_rad);
    const cd c = fit.c[static_cast<Eigen::Index>(i)];
    EXPECT_NEAR(std::abs(c), kTerms[i].amp, tol_c) << "h = " << kTerms[i].h;
    // Phase error of a complex error |dc| << |c|: at most |dc| / |c| rad.
    EXPECT_NEAR(std::arg(c / truth), 0.0, tol_c / kTerms[i].amp) << "h = " << kTerms[i].h;
    worst = std::max(worst, std::abs(c - truth));
  }
  // The residual is the noise: its RMS within 5 % of sigma (the sample RMS of 1e4 normals
  // varies by ~0.7 %).
  EXPECT_NEAR(fit.residual_rms, sigma, 0.05 * sigma);
  chatterlab::testing::record_and_print("worst_abs_c_error_N", worst);
}

TEST(HarmonicFit, EqualsDftBinAndLeastSquaresWhenWindowHoldsWholePeriods) {
  // 12800 Hz, 100 Hz: 128 samples a revolution; 10 revolutions from sample 300.
  const double fs = 12800.0, f0 = 100.0;
  const Eigen::VectorXd x = synth(4000, fs, f0, 3.0, kTerms, 1.0, 7);
  const Eigen::Index begin = 300, n = 1280;
  const std::vector<int> h = {1, 2, 5, 7};
  const HarmonicFit fit = fit_harmonics(x, fs, begin, begin + n, f0, h);
  ASSERT_TRUE(fit.summary.ok());

  // Reference 1: the DFT bin (2/N) sum x_k e^{-j h Omega t_k}, t_k = k / fs.
  // Reference 2: the least-squares solution by normal equations on [1, cos, -sin] columns.
  Eigen::MatrixXd A(n, 1 + 2 * static_cast<Eigen::Index>(h.size()));
  for (Eigen::Index r = 0; r < n; ++r) {
    const double t = static_cast<double>(begin + r) / fs;
    A(r, 0) = 1.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      const auto c = static_cast<Eigen::Index>(1 + 2 * i);
      A(r, c) = std::cos(h[i] * kTwoPi * f0 * t);
      A(r, c + 1) = -std::sin(h[i] * kTwoPi * f0 * t);
    }
  }
  const Eigen::VectorXd p = (A.transpose() * A).ldlt().solve(A.transpose() * x.segment(begin, n));
  EXPECT_NEAR(fit.c0, x.segment(begin, n).mean(), kRoundingN);
  EXPECT_NEAR(fit.c0, p[0], kRoundingN);
  for (std::size_t i = 0; i < h.size(); ++i) {
    cd bin = 0.0;
    for (Eigen::Index k = begin; k < begin + n; ++k)
      bin += x[k] * std::polar(1.0, -h[i] * kTwoPi * f0 * static_cast<double>(k) / fs);
    bin *= 2.0 / static_cast<double>(n);
    const cd c = fit.c[static_cast<Eigen::Index>(i)];
    EXPECT_NEAR(std::abs(c - bin), 0.0, kRoundingN) << "h = " << h[i];
    EXPECT_NEAR(std::abs(c - cd(p[1 + 2 * i], p[2 + 2 * i])), 0.0, kRoundingN) << "h = " << h[i];
  }
}

TEST(HarmonicFit, NonWholePeriodWindowIsExactWithoutNoise) {
  // 137.3 Hz at 10 kHz over 777 samples (10.67 revolutions): the columns are not orthogonal,
  // the DFT bin would leak, the least-squares fit is exact.
  const double fs = 10000.0, f0 = 137.3, c0 = 0.75;
  const Eigen::VectorXd x = synth(2000, fs, f0, c0, kTerms, 0.0, 0);
  const HarmonicFit fit = fit_harmonics(x, fs, 611, 611 + 777, f0, orders(kTerms));
  ASSERT_TRUE(fit.summary.ok());
  EXPECT_NEAR(fit.c0, c0, kRoundingN);
  for (std::size_t i = 0; i < kTerms.size(); ++i)
    EXPECT_NEAR(std::abs(fit.c[static_cast<Eigen::Index>(i)] -
                         std::polar(kTerms[i].amp, kTerms[i].phase_rad)),
                0.0, kRoundingN)
        << "h = " << kTerms[i].h;
  EXPECT_LT(fit.residual_rms, kRoundingN);

  // The same window's DFT bin of h = 1 is off by far more than rounding (leakage): the test
  // above would fail for a fit that skipped the least-squares solve.
  cd bin = 0.0;
  for (Eigen::Index k = 611; k < 611 + 777; ++k)
    bin += x[k] * std::polar(1.0, -kTwoPi * f0 * static_cast<double>(k) / fs);
  bin *= 2.0 / 777.0;
  EXPECT_GT(std::abs(bin - std::polar(kTerms[0].amp, kTerms[0].phase_rad)), 1e-3);
}

TEST(HarmonicFit, MeanAloneWithoutHarmonics) {
  const Eigen::VectorXd x = synth(100, 1000.0, 10.0, 4.0, {}, 1.0, 3);
  const HarmonicFit fit = fit_harmonics(x, 1000.0, 10, 90, 10.0, {});
  ASSERT_TRUE(fit.summary.ok());
  EXPECT_EQ(fit.c.size(), 0);
  EXPECT_NEAR(fit.c0, x.segment(10, 80).mean(), kRoundingN);
}

TEST(HarmonicFit, SubtractRemovesUnbalanceFromExtrapolatedPartToNoiseFloor) {
  // Format sec. 6 "sifs-cut" step 1: fit over the air window [0.05, 1.0] s, subtract from the
  // whole 3.2 s record at 12800 Hz, 9000 rpm; judge in [1.2, 3.2] s, where nothing was fitted.
  const double fs = 12800.0, f0 = 150.0, sigma = 0.3;
  const std::vector<Term> unbalance = {{1, 6.7, 77.5 * kDegToRad}, {2, 1.4, -33.0 * kDegToRad}};
  Eigen::VectorXd noise;
  Eigen::VectorXd x =
      synth(static_cast<Eigen::Index>(3.2 * fs), fs, f0, -1.5, unbalance, sigma, 11, &noise);
  const auto a0 = static_cast<Eigen::Index>(0.05 * fs), a1 = static_cast<Eigen::Index>(1.0 * fs);
  const HarmonicFit fit = fit_harmonics(x, fs, a0, a1, f0, {1, 2});
  ASSERT_TRUE(fit.summary.ok());
  subtract_harmonics(fit, fs, x);

  // Left after subtraction: the noise plus the fit's coefficient errors, a sinusoid of
  // amplitude up to |dc0| + sum |dc_h| everywhere (constant speed: no phase drift).
  const double n_air = static_cast<double>(a1 - a0);
  const double coeff_tol =
      kNoiseSigmas * sigma * (1.0 / std::sqrt(n_air) + 2.0 * std::sqrt(2.0 / n_air));
  const auto c0 = static_cast<Eigen::Index>(1.2 * fs);
  const Eigen::VectorXd left = x.tail(x.size() - c0) - noise.tail(x.size() - c0);
  EXPECT_LT(left.cwiseAbs().maxCoeff(), coeff_tol);
  const double rms =
      std::sqrt(x.tail(x.size() - c0).squaredNorm() / static_cast<double>(x.size() - c0));
  // Noise floor: the RMS of ~2.6e4 normals is sigma within ~0.5 %; allow 2 %.
  EXPECT_NEAR(rms, sigma, 0.02 * sigma);
  chatterlab::testing::record_and_print("extrapolated_residual_max_N", left.cwiseAbs().maxCoeff());
}

TEST(HarmonicFit, ShortWindowFailsTheSummary) {
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(100);
  // Two harmonics need 2 (1 + 4) = 10 samples.
  const HarmonicFit fit = fit_harmonics(x, 1000.0, 0, 9, 10.0, {1, 2});
  EXPECT_TRUE(fit.summary.failed());
  EXPECT_EQ(fit.summary.message, "the window holds 9 samples, fewer than 2 (1 + 2 H) = 10");
  EXPECT_TRUE(std::isnan(fit.c0));
  expect_input_error(
      [&] {
        Eigen::VectorXd y = x;
        subtract_harmonics(fit, 1000.0, y);
      },
      "subtract_harmonics: the fit did not succeed (the window holds 9 samples, "
      "fewer than 2 (1 + 2 H) = 10)");
}

TEST(HarmonicFit, BadInputThrows) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(100);
  expect_input_error([&] { fit_harmonics(x, 0.0, 0, 100, 10.0, {1}); },
                     "fs_hz = 0: must be finite and > 0");
  expect_input_error([&] { fit_harmonics(x, 1000.0, 0, 100, -1.0, {1}); },
                     "fundamental_hz = -1: must be finite and > 0");
  expect_input_error([&] { fit_harmonics(x, 1000.0, 50, 50, 10.0, {1}); },
                     "window [50, 50): must satisfy 0 <= begin < end <= 100 (the signal's length)");
  expect_input_error([&] { fit_harmonics(x, 1000.0, 0, 101, 10.0, {1}); },
                     "window [0, 101): must satisfy 0 <= begin < end <= 100 (the signal's length)");
  expect_input_error(
      [&] {
        fit_harmonics(x, 1000.0, 0, 100, 10.0, {1, 0});
      },
      "harmonics[1] = 0: must be > 0");
  expect_input_error(
      [&] {
        fit_harmonics(x, 1000.0, 0, 100, 10.0, {1, 2, 1});
      },
      "harmonics[2] = 1: repeats harmonics[0]");
  expect_input_error(
      [&] {
        fit_harmonics(x, 1000.0, 0, 100, 10.0, {1, 50});
      },
      "harmonics[1] = 50: h fundamental_hz must be below fs_hz / 2");
  x[7] = std::nan("");
  expect_input_error([&] { fit_harmonics(x, 1000.0, 0, 100, 10.0, {1}); },
                     "x[7] = nan: must be finite");
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
