// RealFft against a naive DFT, round trip and Parseval (CONVENTIONS.md property suite).
#include "analysis/signal/fft.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <thread>
#include <vector>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace signal {
namespace {

// FFT rounding grows like log2(n) eps ||x||; 1e-12 relative covers n <= 1e4 with margin.
constexpr double kRelTol = 1e-12;

Eigen::VectorXd random_signal(Eigen::Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = normal(rng);
  return x;
}

// X[k] = sum_t x[t] exp(-2 pi i k t / n), evaluated directly.
Eigen::VectorXcd naive_dft(const Eigen::VectorXd& x) {
  const Eigen::Index n = x.size();
  Eigen::VectorXcd out(n / 2 + 1);
  for (Eigen::Index k = 0; k <= n / 2; ++k) {
    std::complex<double> sum(0.0, 0.0);
    for (Eigen::Index t = 0; t < n; ++t) {
      const double phase = -2.0 * kPi * static_cast<double>((k * t) % n) / static_cast<double>(n);
      sum += x[t] * std::complex<double>(std::cos(phase), std::sin(phase));
    }
    out[k] = sum;
  }
  return out;
}

class RealFftSizes : public ::testing::TestWithParam<int> {};

TEST_P(RealFftSizes, MatchesNaiveDft) {
  const Eigen::Index n = GetParam();
  const Eigen::VectorXd x = random_signal(n, 100 + static_cast<std::uint64_t>(n));
  RealFft fft(n);
  ASSERT_EQ(fft.bins(), n / 2 + 1);
  const Eigen::VectorXcd fast = fft.forward(x);
  const Eigen::VectorXcd slow = naive_dft(x);
  EXPECT_LT((fast - slow).norm(), kRelTol * slow.norm() + 1e-14);
}

TEST_P(RealFftSizes, RoundTripRecoversTheSignal) {
  const Eigen::Index n = GetParam();
  const Eigen::VectorXd x = random_signal(n, 200 + static_cast<std::uint64_t>(n));
  RealFft fft(n);
  const Eigen::VectorXd back = fft.inverse(fft.forward(x)) / static_cast<double>(n);
  EXPECT_LT((back - x).norm(), kRelTol * x.norm());
}

TEST_P(RealFftSizes, ParsevalHolds) {
  // sum x^2 = (1/n) sum_{k=0}^{n-1} |X[k]|^2, with the bins k > n/2 the mirror of 1..(n-1)/2.
  const Eigen::Index n = GetParam();
  const Eigen::VectorXd x = random_signal(n, 300 + static_cast<std::uint64_t>(n));
  RealFft fft(n);
  const Eigen::VectorXcd X = fft.forward(x);
  double energy = std::norm(X[0]);
  for (Eigen::Index k = 1; k <= n / 2; ++k) {
    const bool nyquist = (n % 2 == 0) && k == n / 2;
    energy += (nyquist ? 1.0 : 2.0) * std::norm(X[k]);
  }
  energy /= static_cast<double>(n);
  EXPECT_NEAR(energy, x.squaredNorm(), kRelTol * x.squaredNorm());
}

INSTANTIATE_TEST_SUITE_P(Lengths, RealFftSizes, ::testing::Values(1, 2, 7, 16, 100, 1023, 4096));

TEST(RealFft, PlanIsReusedAcrossCalls) {
  // The same plan on different inputs gives each input's own transform.
  RealFft fft(64);
  const Eigen::VectorXd a = random_signal(64, 1);
  const Eigen::VectorXd b = random_signal(64, 2);
  const Eigen::VectorXcd fa = fft.forward(a);
  Eigen::VectorXcd fb;
  fft.forward(b, &fb);
  EXPECT_LT((fa - naive_dft(a)).norm(), kRelTol * fa.norm());
  EXPECT_LT((fb - naive_dft(b)).norm(), kRelTol * fb.norm());
}

TEST(RealFft, PlansCanBeMadeFromSeveralThreads) {
  // Planning is serialised by a mutex; each thread owns its RealFft.
  const Eigen::VectorXd x = random_signal(512, 7);
  const Eigen::VectorXcd reference = naive_dft(x);
  std::vector<double> errors(8, 1.0);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < errors.size(); ++t) {
    threads.emplace_back([&, t] {
      for (int repeat = 0; repeat < 20; ++repeat) {
        RealFft fft(512);
        errors[t] = (fft.forward(x) - reference).norm() / reference.norm();
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (double e : errors) EXPECT_LT(e, kRelTol);
}

TEST(RealFft, BadInputIsRejected) {
  try {
    RealFft fft(0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "fft length n = 0: must be >= 1");
  }
  RealFft fft(8);
  try {
    fft.forward(Eigen::VectorXd::Zero(7));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "fft input has 7 samples: plan length is 8");
  }
  try {
    fft.inverse(Eigen::VectorXcd::Zero(4));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "inverse fft input has 4 bins: plan needs n/2 + 1 = 5");
  }
}

}  // namespace
}  // namespace signal
}  // namespace chatterlab
