// Synthetic once-per-revolution sequences built from a known truth, for the tests and the
// measured results of docs/bifurcation.md: a slowly drifting period-one orbit, chatter over
// known depth intervals, white measurement noise.
//
//   depth_n = start + (end - start) n / (N - 1),                  n = 0..N-1
//   x_n = offset + drift depth_n + wobble sin(2 pi n / wobble_period)
//         + sum over episodes of A_e(depth_n) pattern_e(n) + noise_n
//   pattern(n) = cos(2 pi nu n + phase), or independent N(0, 1/2) draws (a cloud)
//   A(b) = A_sat min(1, (b - low) / ramp, (high - b) / ramp) inside [low, high], 0 outside.
//
// nu = 1/2 gives period-two clusters +-A cos(phase), nu = 1/4 four clusters, an irrational nu
// a quasi-periodic ellipse in the Poincare map (000 sec. 5.2); the random cloud stands in for
// the chaotic "cloud of numerous points" with the RMS of a sinusoid of amplitude A. The envelope is
// a function of depth only (no hysteresis), so a decline through [low, inf) ends chatter at `low`.
// A linear ramp is harder to date than the square-root growth of a supercritical Hopf bifurcation:
// its amplitude just past onset is smaller.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

namespace chatterlab {
namespace dynamics {

struct ChatterEpisodeSpec {
  double low_depth_m = 0.0;  // chatter inside [low, high] (m), whatever the run's direction
  double high_depth_m = std::numeric_limits<double>::infinity();
  double amplitude_m = 0.0;   // A_sat
  double ramp_depth_m = 0.0;  // growth from 0 to A_sat over this depth (m); 0: a jump
  double rotation_number = 0.6180339887498949;  // nu, cycles per revolution
  double phase_rad = 0.0;
  bool cloud = false;  // random draws instead of the sinusoid (nu and phase unused)
};

struct OrbitSpec {
  int revolutions = 0;  // N >= 2
  double start_depth_m = 0.0;
  double end_depth_m = 0.0;
  double offset_m = 0.0;       // period-one orbit at depth 0
  double drift_m_per_m = 0.0;  // its change per metre of depth
  double wobble_m = 0.0;       // a slow wander of the period-one orbit
  double wobble_period_revolutions = 1000.0;
  std::vector<ChatterEpisodeSpec> chatter;
  double noise_sigma_m = 0.0;  // white Gaussian measurement noise
  std::uint64_t seed = 1;      // for a local std::mt19937_64
};

struct SyntheticOrbit {
  Eigen::VectorXd depth_m;
  Eigen::VectorXd x_m;
  Eigen::VectorXd amplitude_m;  // true chatter envelope, sum of the episodes' A(depth_n)
};

// @throws InputError if revolutions < 2, noise_sigma_m < 0 or an episode has high < low,
//         a negative amplitude or ramp
SyntheticOrbit synthesize_orbit(const OrbitSpec& spec);

}  // namespace dynamics
}  // namespace chatterlab
