// Chi-square CDF and quantiles (analysis/kalman/chi_square.h) against closed forms, a printed
// table and an arbitrary-precision value.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/kalman/chi_square.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab {
namespace kalman {
namespace {

TEST(LogGamma, MatchesFactorialsAndHalfIntegers) {
  // Gamma(n) = (n - 1)!, Gamma(1/2) = sqrt(pi), Gamma(n + 1/2) = (2n)! sqrt(pi) / (4^n n!)
  // (A&S 6.1.6, 6.1.8, 6.1.12). Tolerance 1e-13: the header's bound on the Stirling remainder
  // plus rounding of the shift's logarithms.
  constexpr double kTolerance = 1e-13;
  double factorial = 1.0;  // (n - 1)!
  for (int n = 1; n <= 30; ++n) {
    if (n > 1) factorial *= n - 1;
    EXPECT_NEAR(log_gamma(n), std::log(factorial), kTolerance * std::max(1.0, std::log(factorial)))
        << "n = " << n;
  }
  EXPECT_NEAR(log_gamma(0.5), 0.5 * std::log(kPi), kTolerance);
  // Gamma(3.5) = 6! sqrt(pi) / (64 * 3!) = 15 sqrt(pi) / 8.
  EXPECT_NEAR(log_gamma(3.5), std::log(15.0 * std::sqrt(kPi) / 8.0), kTolerance);
}

TEST(LogGamma, MatchesTheCLibrary) {
  // glibc's lgamma (an independent implementation; single-threaded here, so its signgam race
  // does not matter). Tolerance 1e-13 relative to max(1, |log Gamma|), as LogGamma above.
  for (double x : {0.1, 0.7, 1.5, 9.99, 15.0, 15.5, 123.25, 4e3, 2.5e5, 1e6}) {
    const double ref = std::lgamma(x);
    EXPECT_NEAR(log_gamma(x), ref, 1e-13 * std::max(1.0, std::abs(ref))) << x;
  }
}

TEST(ChiSquareCdf, MatchesClosedFormsForOneAndTwoDegrees) {
  // F(x; 2) = 1 - e^(-x/2); F(x; 1) = erf(sqrt(x / 2)). Series and continued fraction both
  // appear in the range (the split is at x / 2 = a + 1). Tolerance 5e-14: log Gamma(a) for small
  // a carries ~1e-14 absolute (the Stirling sum at a + 14 cancels ~25 against log of the shift's
  // product), which enters the prefix y^a e^-y / Gamma(a) relatively; plus a few roundings.
  constexpr double kTolerance = 5e-14;
  for (double x : {1e-6, 0.01, 0.5, 1.0, 2.9, 3.1, 7.0, 20.0, 60.0}) {
    EXPECT_NEAR(chi_square_cdf(x, 2.0), 1.0 - std::exp(-0.5 * x), kTolerance) << x;
    EXPECT_NEAR(chi_square_cdf(x, 1.0), std::erf(std::sqrt(0.5 * x)), kTolerance) << x;
  }
  EXPECT_EQ(chi_square_cdf(0.0, 3.0), 0.0);
}

TEST(ChiSquareQuantile, TwoDegreesInvertInClosedForm) {
  // F^-1(p; 2) = -2 ln(1 - p). Relative tolerance 1e-12 (the header's accuracy).
  for (double p : {1e-6, 0.025, 0.3, 0.5, 0.975, 0.999999}) {
    const double exact = -2.0 * std::log1p(-p);
    EXPECT_NEAR(chi_square_quantile(p, 2.0), exact, 1e-12 * exact) << p;
  }
}

TEST(ChiSquareQuantile, MatchesTheNistTable) {
  // NIST/SEMATECH e-Handbook of Statistical Methods, sec. 1.3.6.7.4 (critical values of the
  // chi-square distribution), printed to three decimals: upper critical values at 0.025 are the
  // 0.975 quantiles, lower critical values at 0.975 the 0.025 quantiles. Tolerance: half a unit
  // of the last printed digit.
  constexpr double kHalfDigit = 0.5e-3;
  struct Row {
    double dof, lower, upper;
  };
  for (const Row& r : {Row{1, 0.001, 5.024}, Row{2, 0.051, 7.378}, Row{10, 3.247, 20.483},
                       Row{100, 74.222, 129.561}}) {
    const ChiSquareBand b = chi_square_band(r.dof, 0.95);
    EXPECT_NEAR(b.lower, r.lower, kHalfDigit) << "dof " << r.dof;
    EXPECT_NEAR(b.upper, r.upper, kHalfDigit) << "dof " << r.dof;
    EXPECT_EQ(b.dof, r.dof);
    EXPECT_EQ(b.confidence, 0.95);
  }
}

TEST(ChiSquareQuantile, LargeDegreesMatchArbitraryPrecision) {
  // The mean-NIS band of a whole run has ~1e6 degrees of freedom. Reference: F^-1(0.975; 1e6) =
  // 1002773.701467926 by 200 bisections on mpmath 1.3's regularized gammainc at 40 digits
  // (Wilson-Hilferty gives 1002773.70151, 4.3e-11 relative away). Tolerance 1e-9 relative: the
  // rounding of a ln y - y - log Gamma(a) at a = 5e5 (header) moves the quantile ~2e-11.
  EXPECT_NEAR(chi_square_quantile(0.975, 1e6), 1002773.701467926, 1e-9 * 1002773.7);
}

TEST(ChiSquareQuantile, InvertsTheCdf) {
  // Round trip F(F^-1(p)) = p over small, fractional and large degrees of freedom. Tolerance
  // 1e-12 absolute on p: the quantile's relative accuracy times x f(x) <= ~1.
  for (double dof : {0.5, 1.0, 3.0, 7.5, 40.0, 1e3, 1e5}) {
    for (double p : {0.001, 0.025, 0.5, 0.975, 0.999}) {
      EXPECT_NEAR(chi_square_cdf(chi_square_quantile(p, dof), dof), p, 1e-12)
          << "dof " << dof << ", p " << p;
    }
  }
}

TEST(ChiSquareBand, MeanBandIsTheSumBandScaled) {
  // The mean of 50 chi-square(2) variables: chi-square(100) / 50, i.e. the NIST row for 100.
  const ChiSquareBand b = mean_chi_square_band(50, 2, 0.95);
  EXPECT_NEAR(b.lower, 74.222 / 50, 0.5e-3 / 50);
  EXPECT_NEAR(b.upper, 129.561 / 50, 0.5e-3 / 50);
  EXPECT_TRUE(b.contains(2.0));
  EXPECT_FALSE(b.contains(2.6));
}

TEST(ChiSquareQuantile, RejectsBadArguments) {
  chatterlab::testing::expect_input_error([] { chi_square_quantile(1.0, 2.0); },
                                          "chi-square quantile: p = 1: must be in (0, 1)");
  chatterlab::testing::expect_input_error([] { chi_square_quantile(0.5, 0.0); },
                                          "chi-square quantile: dof = 0: must be > 0");
  chatterlab::testing::expect_input_error([] { chi_square_band(2.0, 1.5); },
                                          "chi-square band: confidence = 1.5: must be in (0, 1)");
  chatterlab::testing::expect_input_error([] { mean_chi_square_band(0.0, 2.0); },
                                          "chi-square band: count = 0: must be >= 1");
}

}  // namespace
}  // namespace kalman
}  // namespace chatterlab
