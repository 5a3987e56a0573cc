// The chi-square distribution for filter consistency bands: its CDF through the regularized
// lower incomplete gamma function, and its quantiles by safeguarded Newton iteration.
//
//   F(x; k) = P(k / 2, x / 2),   P(a, y) = gamma(a, y) / Gamma(a)
//
// P by its power series for y < a + 1 and by the continued fraction of Q = 1 - P otherwise
// (Abramowitz and Stegun, Handbook of Mathematical Functions, 6.5.29 and 6.5.31; the split keeps
// both within a few hundred terms for small a and O(sqrt(a)) terms for large a). log Gamma is
// computed here (not std::lgamma, which writes the global signgam and is not thread-safe).
#pragma once

namespace chatterlab {
namespace kalman {

// log Gamma(x), x > 0: Stirling's series after shifting x above 15 (error < 1e-13 relative to
// max(1, |log Gamma(x)|); ~1e-14 absolute for small x).
double log_gamma(double x);

// P(a, y) for a > 0, y >= 0 (relative error ~3e-14 for a < 100, from log Gamma; ~1e-16 a for
// large a, the rounding of a ln y - y - log Gamma(a)).
double regularized_gamma_p(double a, double y);

// Q(a, y) = 1 - P(a, y), with its relative accuracy kept in the upper tail.
double regularized_gamma_q(double a, double y);

// F(x; dof), dof > 0, x >= 0.
double chi_square_cdf(double x, double dof);

// x with F(x; dof) = p, 0 < p < 1, dof > 0; relative accuracy ~1e-12 for dof up to ~1e7.
// Throws InputError for p or dof out of range.
double chi_square_quantile(double p, double dof);

// Two-sided band of a chi-square(dof) variable: [F^-1((1 - c) / 2), F^-1((1 + c) / 2)].
struct ChiSquareBand {
  double lower = 0.0;
  double upper = 0.0;
  double dof = 0.0;
  double confidence = 0.0;
  bool contains(double v) const { return v >= lower && v <= upper; }
};

// @param dof degrees of freedom, > 0; @param confidence c in (0, 1) (0.95: the 2.5 % and 97.5 %
// quantiles).
ChiSquareBand chi_square_band(double dof, double confidence = 0.95);

// Band of the mean of `count` independent chi-square(dof_each) variables: their sum is
// chi-square(count dof_each), so the band is chi_square_band(count dof_each) / count
// (Bar-Shalom, Li, Kirubarajan 2001, ch. 5: the time-average NIS test). dof = count dof_each.
ChiSquareBand mean_chi_square_band(double count, double dof_each, double confidence = 0.95);

}  // namespace kalman
}  // namespace chatterlab
