#include "analysis/dynamics/orbit_synth.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace dynamics {

namespace {

double envelope(const ChatterEpisodeSpec& e, double depth) {
  if (!(depth >= e.low_depth_m && depth <= e.high_depth_m)) return 0.0;
  if (e.ramp_depth_m <= 0.0) return e.amplitude_m;
  const double rise = (depth - e.low_depth_m) / e.ramp_depth_m;
  const double fall = (e.high_depth_m - depth) / e.ramp_depth_m;
  return e.amplitude_m * std::min({1.0, rise, fall});
}

}  // namespace

SyntheticOrbit synthesize_orbit(const OrbitSpec& spec) {
  if (spec.revolutions < 2) {
    std::ostringstream m;
    m << "orbit.revolutions = " << spec.revolutions << ": must be >= 2";
    throw InputError(m.str());
  }
  if (!(spec.noise_sigma_m >= 0.0)) {
    std::ostringstream m;
    m << "orbit.noise_sigma_m = " << spec.noise_sigma_m << ": must be >= 0";
    throw InputError(m.str());
  }
  for (std::size_t k = 0; k < spec.chatter.size(); ++k) {
    const ChatterEpisodeSpec& e = spec.chatter[k];
    if (!(e.high_depth_m >= e.low_depth_m) || !(e.amplitude_m >= 0.0) || !(e.ramp_depth_m >= 0.0)) {
      std::ostringstream m;
      m << "orbit.chatter[" << k << "]: needs high_depth_m >= low_depth_m, amplitude_m >= 0 "
        << "and ramp_depth_m >= 0";
      throw InputError(m.str());
    }
  }

  const Eigen::Index n = spec.revolutions;
  SyntheticOrbit out;
  out.depth_m.resize(n);
  out.x_m.resize(n);
  out.amplitude_m.resize(n);
  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    const double depth = spec.start_depth_m +
                         (spec.end_depth_m - spec.start_depth_m) * t / static_cast<double>(n - 1);
    double x = spec.offset_m + spec.drift_m_per_m * depth +
               spec.wobble_m * std::sin(kTwoPi * t / spec.wobble_period_revolutions);
    double amplitude = 0.0;
    for (const ChatterEpisodeSpec& e : spec.chatter) {
      const double a = envelope(e, depth);
      const double pattern = e.cloud ? noise(rng) / std::sqrt(2.0)
                                     : std::cos(kTwoPi * e.rotation_number * t + e.phase_rad);
      x += a * pattern;
      amplitude += a;
    }
    if (spec.noise_sigma_m > 0.0) x += spec.noise_sigma_m * noise(rng);
    out.depth_m[i] = depth;
    out.x_m[i] = x;
    out.amplitude_m[i] = amplitude;
  }
  return out;
}

}  // namespace dynamics
}  // namespace chatterlab
