// Angle wrapping shared by the analysis (one definition: the library is compiled as unity
// batches, docs/testing.md#build-time, where two files' private copies would collide).
#pragma once

#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {

// a wrapped to [0, 2 pi).
inline double wrap_2pi(double a) {
  double w = std::fmod(a, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  if (w >= kTwoPi) w = 0.0;  // fmod of a tiny negative value rounds up to 2 pi
  return w;
}

// a wrapped to [0, 360) degrees.
inline double wrap_deg(double a) {
  double w = std::fmod(a, 360.0);
  if (w < 0.0) w += 360.0;
  if (w >= 360.0) w = 0.0;
  return w;
}

// The shorter way round between two angles, in [0, 180] degrees.
inline double circular_distance_deg(double a, double b) {
  const double d = wrap_deg(a - b);
  return std::min(d, 360.0 - d);
}

}  // namespace chatterlab
