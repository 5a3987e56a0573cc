// Random stable discrete systems for the validation of identification methods (001 sec. 3.3
// used MATLAB's rss; this is the discrete construction of notes/001.md sec. 4, seeded so that
// every run draws the same systems).
#pragma once

#include <cstdint>

#include "analysis/sysid/state_space.h"

namespace chatterlab {
namespace sysid {

struct RandomSystemOptions {
  int order = 10;                 // >= 1
  double complex_fraction = 0.8;  // share of the states in complex pole pairs
  double min_radius = 0.85;       // |z| ~ U(min_radius, max_radius), 0 < min <= max < 1
  double max_radius = 0.995;
  double min_angle = 0.02;  // arg z ~ U(min_angle, pi - min_angle) for pairs (rad)
  double d_scale = 0.5;     // D ~ d_scale N(0, 1)
};

// A in real block-diagonal form (2 x 2 rotation-scaling blocks for pairs, scalars for real
// poles of either sign), then a random orthogonal similarity; B, C ~ N(0, 1).
// @throws InputError for options outside their ranges.
DiscreteStateSpace random_stable_system(const RandomSystemOptions& options, double sample_rate_hz,
                                        std::uint64_t seed);

}  // namespace sysid
}  // namespace chatterlab
