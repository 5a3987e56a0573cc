// Cubic-spline resampling of a uniformly sampled signal onto a finer (or coarser) uniform grid,
// as 000 sec. 6.1 does before running the EKFs ("re-sampled by spline-fit interpolation to a
// time step of 5e-7 s": 2.5e-6 s simulated and 1e-5 s measured records).
//
// The interpolant through samples y_i at t_i = i h is, on [t_i, t_i+1] with u = (t - t_i) / h,
//   s(t) = (1 - u) y_i + u y_i+1 + h^2 / 6 [((1 - u)^3 - (1 - u)) M_i + (u^3 - u) M_i+1],
// where the second derivatives M solve M_i-1 + 4 M_i + M_i+1 = 6 (y_i-1 - 2 y_i + y_i+1) / h^2
// at the interior knots, closed by one of two end conditions:
//   not-a-knot: s''' continuous at t_1 and t_n-2 (M_0 = 2 M_1 - M_2, the mirror at the end); the
//     first and last interior equations become 6 M_1 = rhs_1 and 6 M_n-2 = rhs_n-2. MATLAB's
//     spline() and interp1(..., 'spline'), which 000 used, close the spline this way. It
//     reproduces cubics exactly and keeps O(h^4) accuracy up to the ends.
//   natural: M_0 = M_n-1 = 0. Reproduces straight lines only; O(h^2) error near the ends of a
//     signal whose curvature does not vanish there.
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace estimate {

enum class SplineEnd { kNotAKnot, kNatural };

// Number of output samples: t_j = j step_out_s for j = 0, 1, ... while t_j <= (n - 1) step_in_s
// (a relative slack of 1e-9 step keeps an exact multiple of the step on the grid).
Eigen::Index resampled_count(Eigen::Index n, double step_in_s, double step_out_s);

// Resamples `samples` (sample i at time i step_in_s) at times j step_out_s, j = 0 ..
// resampled_count - 1. Throws InputError unless samples.size() >= 4, every sample is finite and
// both steps are finite and > 0.
Eigen::VectorXd resample_cubic_spline(const Eigen::Ref<const Eigen::VectorXd>& samples,
                                      double step_in_s, double step_out_s,
                                      SplineEnd end = SplineEnd::kNotAKnot);

}  // namespace estimate
}  // namespace chatterlab
