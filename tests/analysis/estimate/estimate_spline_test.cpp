#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/estimate/spline_resample.h"
#include "tests/support/record_property.h"

namespace chatterlab {
namespace estimate {
namespace {

using chatterlab::testing::record;

Eigen::VectorXd sampled(double (*f)(double), Eigen::Index n, double h) {
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y[i] = f(static_cast<double>(i) * h);
  return y;
}

double cubic(double t) { return 2.0 - 3.0 * t + 0.5 * t * t + 4.0 * t * t * t; }
double line(double t) { return -1.5 + 7.0 * t; }
// 1 kHz, near the tool's 0.9 kHz mode (000 sec. 5.1).
double sine(double t) { return std::sin(2.0 * kPi * 1000.0 * t + 0.3); }

// Largest |resampled - f| over the output grid, from output index `skip` to size - 1 - skip.
double max_error(const Eigen::VectorXd& out, double (*f)(double), double step_out,
                 Eigen::Index skip) {
  double e = 0.0;
  for (Eigen::Index j = skip; j + skip < out.size(); ++j) {
    e = std::max(e, std::abs(out[j] - f(static_cast<double>(j) * step_out)));
  }
  return e;
}

TEST(ResampledCount, CoversTheRecordOnTheOutputGrid) {
  // 000 sec. 6.1: 0.2 s at 100 kHz (20,001 samples) to 5e-7 s: 400,001 samples, the last at 0.2 s.
  EXPECT_EQ(resampled_count(20001, 1e-5, 5e-7), 400001);
  EXPECT_EQ(resampled_count(80001, 2.5e-6, 5e-7), 400001);
  // A step that does not divide the span stops before the last input sample.
  EXPECT_EQ(resampled_count(11, 1.0, 3.0), 4);  // 0, 3, 6, 9 (<= 10)
  EXPECT_EQ(resampled_count(0, 1.0, 1.0), 0);
}

TEST(SplineResample, NotAKnotReproducesCubicsExactly) {
  // Reference: a not-a-knot spline through samples of a cubic is that cubic (closed form).
  const double h = 0.1;
  const Eigen::VectorXd y = sampled(cubic, 12, h);
  const Eigen::VectorXd out = resample_cubic_spline(y, h, h / 7.0, SplineEnd::kNotAKnot);
  ASSERT_EQ(out.size(), 78);
  const double err = max_error(out, cubic, h / 7.0, 0);
  record("cubic_max_error", err);
  EXPECT_LT(err, 1e-12);  // rounding of values of order 10
}

TEST(SplineResample, NaturalReproducesLinesButNotCubicEnds) {
  const double h = 0.1;
  const Eigen::VectorXd out_line =
      resample_cubic_spline(sampled(line, 12, h), h, h / 5.0, SplineEnd::kNatural);
  EXPECT_LT(max_error(out_line, line, h / 5.0, 0), 1e-12);
  // The cubic's second derivative (1 + 24 t) is not 0 at the ends: the natural spline misses it
  // there (O(h^2)), while not-a-knot is exact.
  const Eigen::VectorXd out_cubic =
      resample_cubic_spline(sampled(cubic, 12, h), h, h / 5.0, SplineEnd::kNatural);
  EXPECT_GT(max_error(out_cubic, cubic, h / 5.0, 0), 1e-4);
}

TEST(SplineResample, PassesThroughTheKnots) {
  const double h = 1e-5;
  const Eigen::VectorXd y = sampled(sine, 200, h);
  for (SplineEnd end : {SplineEnd::kNotAKnot, SplineEnd::kNatural}) {
    const Eigen::VectorXd out = resample_cubic_spline(y, h, h / 20.0, end);
    for (Eigen::Index i = 0; i < y.size(); ++i) EXPECT_NEAR(out[20 * i], y[i], 1e-15);
  }
}

TEST(SplineResample, SmoothSignalAt100kHzTo5e7Seconds) {
  // 000 sec. 6.1's measured case: 1e-5 s to 5e-7 s. Reference: the sampled function itself;
  // bound: the clamped-spline error bound (5/384) h^4 max|f''''| (Hall and Meyer 1976), with a
  // factor 2 for the not-a-knot ends.
  const double h = 1e-5;
  const Eigen::VectorXd y = sampled(sine, 2001, h);
  const Eigen::VectorXd out = resample_cubic_spline(y, h, 5e-7);
  const double w = 2.0 * kPi * 1000.0;
  const double bound = 2.0 * 5.0 / 384.0 * std::pow(h, 4) * std::pow(w, 4);
  const double err = max_error(out, sine, 5e-7, 0);
  record("sine_1kHz_max_error", err);
  record("sine_1kHz_bound", bound);
  EXPECT_LT(err, bound);
  // Natural ends: the same accuracy away from the ends (here 10 input samples in), worse at them.
  const Eigen::VectorXd nat = resample_cubic_spline(y, h, 5e-7, SplineEnd::kNatural);
  EXPECT_LT(max_error(nat, sine, 5e-7, 200), bound);
  EXPECT_GT(max_error(nat, sine, 5e-7, 0), bound);
}

TEST(SplineResample, FourthOrderConvergence) {
  // Halving h divides the error by ~16 (O(h^4)); the not-a-knot ends move the ratio a little
  // (18.7 measured): accept 12..24.
  const double e1 =
      max_error(resample_cubic_spline(sampled(sine, 201, 2e-5), 2e-5, 5e-7), sine, 5e-7, 0);
  const double e2 =
      max_error(resample_cubic_spline(sampled(sine, 401, 1e-5), 1e-5, 5e-7), sine, 5e-7, 0);
  record("convergence_ratio", e1 / e2);
  EXPECT_GT(e1 / e2, 12.0);
  EXPECT_LT(e1 / e2, 24.0);
}

TEST(SplineResample, RejectsBadInput) {
  const Eigen::VectorXd three = Eigen::VectorXd::Zero(3);
  try {
    resample_cubic_spline(three, 1.0, 0.5);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "resample.samples.size() = 3: must be >= 4 (a cubic spline needs four knots)");
  }
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(5);
  bad[2] = std::nan("");
  try {
    resample_cubic_spline(bad, 1.0, 0.5);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "resample.samples[2] = nan: must be finite");
  }
  const Eigen::VectorXd ok = Eigen::VectorXd::Zero(5);
  try {
    resample_cubic_spline(ok, 0.0, 0.5);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "resample.step_in_s = 0: must be finite and > 0");
  }
  try {
    resample_cubic_spline(ok, 1.0, -1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "resample.step_out_s = -1: must be finite and > 0");
  }
}

}  // namespace
}  // namespace estimate
}  // namespace chatterlab
