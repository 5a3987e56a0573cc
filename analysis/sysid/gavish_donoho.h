// The optimal hard threshold for singular values of Gavish and Donoho ("The optimal hard
// threshold for singular values is 4/sqrt(3)", IEEE Trans. Inf. Theory 60, 2014), which 001
// eqs 3.17-3.19 use to choose the ERA model order. 001 prints the rules garbled (3.17 calls the
// noise's standard deviation a variance; 3.18 has no square root over mu); notes/001.md sec. 3
// restates them, and these are the paper's forms:
//
// For an m x n matrix, m <= n, aspect ratio b = m / n, and white noise of standard deviation
// sigma in each entry:
//   known sigma:    tau = lambda*(b) sqrt(n) sigma,
//                   lambda*(b) = sqrt(2 (b + 1) + 8 b / ((b + 1) + sqrt(b^2 + 14 b + 1)))
//   unknown sigma:  tau = omega(b) median(singular values),  omega(b) = lambda*(b) / sqrt(mu_b)
// where mu_b is the median of the Marchenko-Pastur law of ratio b:
//   integral from (1 - sqrt b)^2 to mu_b of sqrt(((1 + sqrt b)^2 - t)(t - (1 - sqrt b)^2))
//   / (2 pi b t) dt = 1/2     (001 eq. 3.19 is its b = 1 case).
// lambda*(1) = 4 / sqrt(3) = 2.3094, mu_1 = 0.65278, omega(1) = 2.8584 (notes/001.md sec. 3).
#pragma once

namespace chatterlab {
namespace sysid {

// lambda*(b). @throws InputError unless 0 < b <= 1.
double gavish_donoho_lambda(double b);

// The Marchenko-Pastur median mu_b, by bisection on the integral above (Gauss-Legendre after
// the substitution t = a + (c - a) sin^2(theta), which removes the square-root end
// singularities), to 1e-12. @throws InputError unless 0 < b <= 1.
double marchenko_pastur_median(double b);

// omega(b) = lambda*(b) / sqrt(mu_b). @throws InputError unless 0 < b <= 1.
double gavish_donoho_omega(double b);

}  // namespace sysid
}  // namespace chatterlab
