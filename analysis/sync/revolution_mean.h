// Mean of x, y over whole tachometer revolutions as a function of the tach phase (000 sec. 3.1:
// the mean non-cutting contour; 000 sec. 5.1: the measured revolution compared with the
// simulation).
//
// Revolution k (edges e_k, e_(k+1), tach_angle.h) is resampled onto the phase grid
// phi_j = 2 pi j / N, j = 0..N-1, at the fractional sample positions
//   p_kj = e_k + (j / N) (e_(k+1) - e_k)
// by linear interpolation between the neighbouring samples, and the resampled revolutions
// are averaged point by point. Every revolution is stretched to its own length, so a
// revolution of a drifting speed is compared angle for angle (the "rescaled as necessary"
// of 000 sec. 3.1 in time; docs/cut-processing.md).
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/sync/tach_angle.h"

namespace chatterlab {
namespace sync {

// Tachometer revolutions first .. first + count - 1.
struct RevolutionRange {
  int first = 0;
  int count = 0;
};

struct RevolutionMean {
  Eigen::VectorXd phase_rad;  // grid phi_j = 2 pi j / N
  Eigen::VectorXd x_m, y_m;   // mean over the revolutions at each phase
  // Sample standard deviation over the revolutions at each phase (noise, or chatter when it
  // exceeds the noise); NaN with one revolution.
  Eigen::VectorXd std_x_m, std_y_m;
  RevolutionRange revolutions;
  double start_s = std::numeric_limits<double>::quiet_NaN();  // edge e_first / fs
  double end_s = std::numeric_limits<double>::quiet_NaN();    // edge e_(first + count) / fs
};

// The whole tachometer revolutions inside [start_s, end_s] (both edges inside; t = i / fs).
// count = 0 when none fits. Requires tach.summary.ok (InputError otherwise).
RevolutionRange whole_revolutions_in(const TachAngle& tach, double start_s, double end_s);

// Mean of x, y over `range` on an N-point phase grid (see above).
//
// @param x_m, y_m  one value per sample of the tachometer record (sizes == tach.phase_rad)
// @param phase_points  N >= 8
// @throws InputError if tach did not succeed, sizes differ, N < 8 or range is empty or not
//         within 0 .. tach.revolutions - 1
RevolutionMean mean_revolution(const Eigen::Ref<const Eigen::VectorXd>& x_m,
                               const Eigen::Ref<const Eigen::VectorXd>& y_m, const TachAngle& tach,
                               RevolutionRange range, int phase_points);

// A periodic function given on the uniform grid 2 pi j / N (values[j]), evaluated at any phase
// by linear interpolation (wrapping from the last point to the first).
double periodic_interpolate(const Eigen::Ref<const Eigen::VectorXd>& values, double phase_rad);

}  // namespace sync
}  // namespace chatterlab
