// Mathematical constants and unit factors, defined once for the whole project. SI inside;
// the factors convert at the interfaces where a value carries another unit (_deg, _rpm, _mm).
#pragma once

namespace chatterlab {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

// Angles: rad = deg * kDegToRad, deg = rad * kRadToDeg.
inline constexpr double kDegToRad = kPi / 180.0;
inline constexpr double kRadToDeg = 180.0 / kPi;

// Spindle speed: omega [rad/s] = rpm * kRpmToRadPerS; one revolution lasts 60 / rpm s.
inline constexpr double kRpmToRadPerS = kTwoPi / 60.0;
inline constexpr double kSecondsPerMinute = 60.0;

// Lengths: m = mm * kMmToM; mm = m * kMToMm; um = m * kMToUm.
inline constexpr double kMmToM = 1e-3;
inline constexpr double kMToMm = 1e3;
inline constexpr double kMToUm = 1e6;

}  // namespace chatterlab
