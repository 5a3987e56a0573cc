#include "analysis/kalman/chi_square.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/common/require.h"

namespace chatterlab {
namespace kalman {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kTiny = 1e-300;

// Iterations allowed to a series or continued fraction of parameter a: both need O(sqrt(a))
// terms near y = a, a few hundred for small a.
int max_terms(double a) { return 1000 + static_cast<int>(50.0 * std::sqrt(a)); }

// log of y^a e^-y / Gamma(a).
double log_prefix(double a, double y) { return a * std::log(y) - y - log_gamma(a); }

// P(a, y) = y^a e^-y / Gamma(a) * sum_n y^n / (a (a + 1) ... (a + n)) (A&S 6.5.29).
double gamma_p_series(double a, double y) {
  double term = 1.0 / a;
  double sum = term;
  const int n_max = max_terms(a);
  for (int n = 1; n < n_max; ++n) {
    term *= y / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEpsilon) break;
  }
  return sum * std::exp(log_prefix(a, y));
}

// Q(a, y) = y^a e^-y / Gamma(a) * 1 / (y + 1 - a - 1 (1 - a) / (y + 3 - a - 2 (2 - a) / ...))
// (A&S 6.5.31 in its even contraction), by the modified Lentz method.
double gamma_q_fraction(double a, double y) {
  double b = y + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  const int n_max = max_terms(a);
  for (int i = 1; i < n_max; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return std::exp(log_prefix(a, y)) * h;
}

}  // namespace

double log_gamma(double x) {
  // Gamma(x) = Gamma(x + n) / (x (x + 1) ... (x + n - 1)) (one logarithm of the product, which
  // stays below 15! ~ 1.3e12 for x > 0); then Stirling's series (A&S 6.1.41) to the x^-7 term,
  // whose truncation error at x >= 15 is below 1 / (1188 15^9) ~ 2e-14.
  double product = 1.0;
  while (x < 15.0) {
    product *= x;
    x += 1.0;
  }
  const double inv = 1.0 / x;
  const double inv2 = inv * inv;
  const double series =
      inv * (1.0 / 12.0 - inv2 * (1.0 / 360.0 - inv2 * (1.0 / 1260.0 - inv2 / 1680.0)));
  return (x - 0.5) * std::log(x) - x + 0.91893853320467274178 + series - std::log(product);
}

double regularized_gamma_p(double a, double y) {
  if (y <= 0.0) return 0.0;
  if (y < a + 1.0) return gamma_p_series(a, y);
  return 1.0 - gamma_q_fraction(a, y);
}

double regularized_gamma_q(double a, double y) {
  if (y <= 0.0) return 1.0;
  if (y < a + 1.0) return 1.0 - gamma_p_series(a, y);
  return gamma_q_fraction(a, y);
}

double chi_square_cdf(double x, double dof) { return regularized_gamma_p(0.5 * dof, 0.5 * x); }

double chi_square_quantile(double p, double dof) {
  require_rule(p > 0.0 && p < 1.0, "chi-square quantile: p", p, "must be in (0, 1)");
  require_rule(std::isfinite(dof) && dof > 0.0, "chi-square quantile: dof", dof, "must be > 0");
  const double a = 0.5 * dof;
  // Upper half: solve Q(x / 2) = 1 - p (1 - p is exact for p >= 0.5, and Q keeps its relative
  // accuracy in the tail where 1 - P would not); lower half: P(x / 2) = p. g(x) below is
  // increasing in x either way, with g' = f, the chi-square density
  // f(x) = e^((a-1) ln(x/2) - x/2) / (2 Gamma(a)).
  const bool upper = p > 0.5;
  const double target = upper ? 1.0 - p : p;
  const auto g = [&](double x) {
    return upper ? target - regularized_gamma_q(a, 0.5 * x) : regularized_gamma_p(a, 0.5 * x) - p;
  };
  // Bracket [lo, hi] with g(lo) < 0 <= g(hi), then Newton steps, falling back to bisection
  // when a step leaves the bracket.
  double lo = 0.0;
  double hi = std::max(dof, 1.0);
  while (g(hi) < 0.0) {
    lo = hi;
    hi *= 2.0;
  }
  double x = dof > lo && dof < hi ? dof : 0.5 * (lo + hi);
  const double lg = log_gamma(a);
  for (int it = 0; it < 300; ++it) {
    const double f = g(x);
    if (f < 0.0) {
      lo = x;
    } else {
      hi = x;
    }
    const double pdf = 0.5 * std::exp((a - 1.0) * std::log(0.5 * x) - 0.5 * x - lg);
    double next = pdf > 0.0 && std::isfinite(pdf) ? x - f / pdf : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::abs(next - x);
    x = next;
    if (step <= 1e-14 * x || hi - lo <= 1e-15 * hi) break;
  }
  return x;
}

ChiSquareBand chi_square_band(double dof, double confidence) {
  require_rule(confidence > 0.0 && confidence < 1.0, "chi-square band: confidence", confidence,
               "must be in (0, 1)");
  ChiSquareBand b;
  b.dof = dof;
  b.confidence = confidence;
  b.lower = chi_square_quantile(0.5 * (1.0 - confidence), dof);
  b.upper = chi_square_quantile(0.5 * (1.0 + confidence), dof);
  return b;
}

ChiSquareBand mean_chi_square_band(double count, double dof_each, double confidence) {
  require_rule(std::isfinite(count) && count >= 1.0, "chi-square band: count", count,
               "must be >= 1");
  ChiSquareBand b = chi_square_band(count * dof_each, confidence);
  b.lower /= count;
  b.upper /= count;
  return b;
}

}  // namespace kalman
}  // namespace chatterlab
