// Edge detection on pulse channels (dynamometer zero-count, laser tachometer).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace chatterlab {
namespace signal {

// Rising crossings of `threshold` with hysteresis, as fractional sample indices.
//
// A crossing is reported when the signal reaches `threshold` (x[i] >= threshold) while the
// detector is armed; the detector arms only after the signal has been strictly below
// `threshold - hysteresis`, so noise chattering around the threshold yields one edge.
// The detector starts disarmed: a record that begins above (or just below) the threshold
// does not report a spurious edge at its first samples.
//
// The reported position is the linear interpolation between samples i-1 and i,
//   edge = (i - 1) + (threshold - x[i-1]) / (x[i] - x[i-1]),
// i.e. the last upward passage through the threshold before the trigger sample. NaN samples
// neither arm nor trigger the detector; the interpolation then spans the NaN gap.
//
// @param x          samples, any length (an empty or 1-sample signal has no edges)
// @param threshold  level of the crossing, in the unit of x (e.g. 2.5 V for a 0/5 V pulse)
// @param hysteresis re-arm margin below threshold, same unit, >= 0
// @return increasing fractional indices in [0, x.size() - 1]
// @throws InputError if threshold is not finite or hysteresis is negative or not finite
std::vector<double> rising_edges(const Eigen::Ref<const Eigen::VectorXd>& x, double threshold,
                                 double hysteresis);

}  // namespace signal
}  // namespace chatterlab
