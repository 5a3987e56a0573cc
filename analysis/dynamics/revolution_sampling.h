// Once-per-revolution sampling (000 sec. 5.2): the value of a signal each time the tool angle
// theta_1 passes the same angle theta_s, the x_n of the bifurcation diagrams (x_n against
// axial depth) and of the Poincare maps (x_n against x_(n-1)). See docs/bifurcation.md.
#pragma once

#include <Eigen/Core>

namespace chatterlab {
namespace dynamics {

// The instants at which theta_1 passes theta_s + 2 pi k, k integer, in one record.
struct RevolutionCrossings {
  // Fractional sample index of crossing n: with theta(i) <= theta_s + 2 pi k < theta(i+1),
  //   position = i + (theta_s + 2 pi k - theta(i)) / (theta(i+1) - theta(i)),
  // i.e. theta_1 interpolated linearly between samples. Time after the first sample is
  // position / sample_rate_hz. Increasing.
  Eigen::VectorXd sample_position;
  // k of crossing n (the crossing is at theta_1 = theta_s + 2 pi k): consecutive integers.
  Eigen::VectorXi revolution;
  // Length of the angle record the crossings came from; sample_at_crossings checks it.
  Eigen::Index sample_count = 0;

  Eigen::Index size() const { return sample_position.size(); }
};

// Every crossing of theta_s + 2 pi k inside [theta(0), theta(end)], both ends included.
//
// @param theta_rad    theta_1 of every sample, rad: unwrapped, finite, strictly increasing
//                     (e.g. from tachometer edges); any length (fewer than one revolution
//                     gives no crossing or one)
// @param theta_s_rad  the sampling angle, rad; finite; only its value modulo 2 pi matters
// @throws InputError naming the first sample that is not finite or not above its predecessor
RevolutionCrossings revolution_crossings(const Eigen::Ref<const Eigen::VectorXd>& theta_rad,
                                         double theta_s_rad);

// A signal sampled at the crossings, by linear interpolation between the neighbouring samples:
//   x_n = (1 - f) signal(i) + f signal(i + 1),   i = floor(position), f = position - i.
// Works for the measured deflection and for any companion signal on the same time base (the
// other axis, the axial depth at that instant, ...). Interpolation error for a smooth signal:
// at most max|signal''| / 8 in sample units (e.g. A (2 pi f / fs)^2 / 8 for a sinusoid).
//
// @param signal  one value per sample of the angle record (size == crossings.sample_count)
// @throws InputError if the sizes differ
Eigen::VectorXd sample_at_crossings(const RevolutionCrossings& crossings,
                                    const Eigen::Ref<const Eigen::VectorXd>& signal);

}  // namespace dynamics
}  // namespace chatterlab
