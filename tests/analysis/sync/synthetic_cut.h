// Synthetic cut records with known truth for the sync tests, built the way app/synth_cut.cpp
// writes them (the tests may not depend on app): tip deflection from milling::simulate, a
// runout contour fixed in the tool (periodic in theta_1) at the sensors, white noise at the tip,
// sensor = (tip + noise) / sensor_to_tip + contour, and a 0/5 V tachometer pulse whose rising
// edge is where theta_1 equals the offset angle. Air revolutions first (tip deflection 0), then
// the cut starting at theta_1 = 0 from rest, as the simulator starts.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "analysis/milling/simulation.h"

namespace chatterlab {
namespace sync {
namespace testing {

constexpr double kPi = 3.141592653589793238463;
constexpr double kTachHigh_V = 5.0;

// 000 table 5.2, incline trial 1 (unequal teeth), and 000 sec. 5.2 cut conditions.
inline milling::SimulationOptions table52_incline1() {
  milling::SimulationOptions o;
  o.teeth = 2;
  o.radius_m = 6.35e-3;
  o.modal_x = {0.03134, 22.21, 9.84e5};
  o.coefficients = {milling::cutting_coefficients(2.483e8, 2.196e8),
                    milling::cutting_coefficients(6.641e9, 4.154e9)};
  o.spindle_rpm = 15000.0;
  o.feed_per_tooth_m = 0.0635e-3;
  o.radial_immersion_m = 0.382e-3;
  o.steps_per_tooth = 800;
  return o;
}

// 000 sec. 5.1: hammer-test modal parameters and dynamometer coefficients (alike teeth).
inline milling::SimulationOptions hammer_and_dynamometer() {
  milling::SimulationOptions o = table52_incline1();
  o.modal_x = {0.03211, 13.39, 1.023e6};
  o.coefficients = {milling::cutting_coefficients(5.89e8, 3.19e8),
                    milling::cutting_coefficients(5.89e8, 3.19e8)};
  return o;
}

// Contour of the spinning tool at the sensors on +x and +y (app/synth_cut.cpp): eccentricity
// e and out-of-roundness harmonics h = 2, 3, ... with fixed phases.
struct Contour {
  double eccentricity_m = 3e-6;
  double eccentricity_angle_rad = 0.7;
  std::vector<double> harmonic_m = {0.8e-6, 0.4e-6, 0.2e-6};
  std::vector<double> harmonic_phase_rad = {0.3, 2.1, 4.0};

  double x_m(double theta1) const {
    double c = eccentricity_m * std::sin(theta1 + eccentricity_angle_rad);
    for (std::size_t h = 0; h < harmonic_m.size(); ++h) {
      const double kh = static_cast<double>(h + 2);
      c += harmonic_m[h] * std::cos(kh * (kPi / 2 - theta1) + harmonic_phase_rad[h]);
    }
    return c;
  }
  double y_m(double theta1) const {
    double c = eccentricity_m * std::cos(theta1 + eccentricity_angle_rad);
    for (std::size_t h = 0; h < harmonic_m.size(); ++h) {
      const double kh = static_cast<double>(h + 2);
      c += harmonic_m[h] * std::cos(-kh * theta1 + harmonic_phase_rad[h]);
    }
    return c;
  }
};

// Tachometer volts at a sample whose theta_1 is `theta1` (unwrapped or not) when theta_1
// advances `rad_per_sample` per sample: 5 V for `width` samples after each instant theta_1 =
// offset (mod 2 pi), with two-sample linear ramps centred on the instant (linear interpolation
// at 2.5 V recovers it exactly at constant speed).
inline double tach_volts(double theta1, double offset_rad, double rad_per_sample, double width) {
  double u = std::fmod(theta1 - offset_rad, 2 * kPi);
  if (u < 0) u += 2 * kPi;
  u /= rad_per_sample;  // samples since the edge
  const double period = 2 * kPi / rad_per_sample;
  if (u > period / 2) u -= period;
  const double rise = std::clamp(0.5 * (u + 1.0), 0.0, 1.0);
  const double fall = std::clamp(0.5 * (width - u + 1.0), 0.0, 1.0);
  return kTachHigh_V * std::min(rise, fall);
}

struct CutSpec {
  milling::SimulationOptions params = table52_incline1();
  double depth_m = 1e-3;
  // A ramp from depth_m to depth_end_m at revolutions_per_mm (cut_revolutions is then the
  // ramp's length) when depth_end_m differs from depth_m.
  double depth_end_m = std::numeric_limits<double>::quiet_NaN();
  double revolutions_per_mm = 1290.0;  // 000 sec. 5.2
  double fs_hz = 100000.0;             // 400 samples per revolution at 15,000 rpm
  int air_revolutions = 12;
  int cut_revolutions = 60;
  int tail_revolutions = 2;  // air after the cut
  double offset_deg = 147.3;
  double noise_tip_m = 5e-7;
  double sensor_to_tip = 2.78;
  Contour contour;
  std::uint64_t seed = 20240611;
};

struct CutRecord {
  Eigen::VectorXd x_sensor_m, y_sensor_m, tach_V;
  Eigen::VectorXd x_tip_m, y_tip_m;  // true tip deflection (no noise, no contour)
  Eigen::VectorXd theta1_rad;        // true theta_1, unwrapped (0 at sample 0)
  int samples_per_revolution = 0;
  double air_start_s = 0.0, air_end_s = 0.0;  // as app/synth_cut.cpp writes them
  double cut_start_s = 0.0, cut_end_s = 0.0;
};

inline CutRecord make_cut(const CutSpec& s) {
  const double per_rev = s.fs_hz * 60.0 / s.params.spindle_rpm;
  const auto P = static_cast<int>(std::lround(per_rev));
  if (std::abs(per_rev - P) > 1e-9) throw std::logic_error("whole samples per revolution only");
  const int S = s.params.teeth * s.params.steps_per_tooth;
  if (S % P != 0) throw std::logic_error("steps per revolution must be a multiple of P");
  const int decimation = S / P;
  milling::SimulationOptions o = s.params;
  const bool ramp = !std::isnan(s.depth_end_m) && s.depth_end_m != s.depth_m;
  o.depth = ramp ? milling::DepthProfile::ramp(s.depth_m, s.depth_end_m, s.revolutions_per_mm)
                 : milling::DepthProfile::constant(s.depth_m, s.cut_revolutions);
  const int cut_revolutions = milling::simulation_grid(o).revolutions;
  milling::RecordingRequest rec;
  rec.trace_revolutions = cut_revolutions;
  const milling::SimulationResult sim = milling::simulate(o, rec);
  if (!sim.summary.ok) throw std::logic_error("simulation failed: " + sim.summary.message);

  CutRecord r;
  r.samples_per_revolution = P;
  const Eigen::Index n_air = static_cast<Eigen::Index>(s.air_revolutions) * P;
  const Eigen::Index n_cut = static_cast<Eigen::Index>(cut_revolutions) * P;
  const Eigen::Index n = n_air + n_cut + static_cast<Eigen::Index>(s.tail_revolutions) * P;
  r.x_sensor_m.resize(n);
  r.y_sensor_m.resize(n);
  r.tach_V.resize(n);
  r.x_tip_m = Eigen::VectorXd::Zero(n);
  r.y_tip_m = Eigen::VectorXd::Zero(n);
  r.theta1_rad.resize(n);
  std::mt19937_64 rng(s.seed);
  std::normal_distribution<double> noise(0.0, s.noise_tip_m);
  const double offset_rad = s.offset_deg * kPi / 180.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double theta1 = 2 * kPi * static_cast<double>(i) / P;
    r.theta1_rad[i] = theta1;
    if (i >= n_air && i < n_air + n_cut) {
      const auto k = static_cast<std::size_t>((i - n_air) * decimation);
      r.x_tip_m[i] = sim.trace.x_m[k];
      r.y_tip_m[i] = sim.trace.y_m[k];
    }
    r.x_sensor_m[i] = (r.x_tip_m[i] + noise(rng)) / s.sensor_to_tip + s.contour.x_m(theta1);
    r.y_sensor_m[i] = (r.y_tip_m[i] + noise(rng)) / s.sensor_to_tip + s.contour.y_m(theta1);
    r.tach_V[i] = tach_volts(theta1, offset_rad, 2 * kPi / P, 0.05 * P);
  }
  const double T = 60.0 / s.params.spindle_rpm;
  r.air_end_s = (s.air_revolutions - 1) * T;
  r.cut_start_s = s.air_revolutions * T;
  r.cut_end_s = (s.air_revolutions + cut_revolutions) * T;
  return r;
}

}  // namespace testing
}  // namespace sync
}  // namespace chatterlab
