// Synthetic cut records with known truth (EXPERIMENT_FORMAT.md, kind: cut): a milling run
// simulated with given modal parameters and per-tooth coefficients (milling/simulation.h), seen
// through capacitive sensors and a laser tachometer as 000 sec. 3.1 describes them. Used by
// `chatterlab synth` and by the tests of the cut chain.
//
// Record: air_revolutions of spinning before the cut (tip deflection 0), the simulated cut
// (starting from rest at theta_1 = 0, as the simulator starts), tail_revolutions of air after
// it; P = fs 60 / rpm samples per revolution (whole), sample i at theta_1 = 2 pi (i mod P) / P.
// At sample i (000 sec. 3.1, sensors on +x and +y):
//   sensor_x = (x_tip + n_x) / sensor_to_tip + c_x(theta_1),  likewise y,
// with n white Gaussian noise at the tip (noise_tip_m) and c the tool's contour fixed in the tool
// (runout and out-of-roundness, periodic in theta_1; ToolContour). The tachometer is 0 V with a
// pulse of high_V for tach_width_revolutions P samples from each instant where theta_1 equals
// the offset angle (the rising edge, EXPERIMENT_FORMAT.md), ramps two samples wide centred on
// the instant so that linear interpolation at half amplitude recovers it exactly.
//
// Randomness: one std::mt19937_64 seeded with `seed`: first the harmonic phases when the
// contour does not give them (uniform in [0, 2 pi), one per harmonic), then n_x, n_y at each
// sample in order.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace sync {

// Contour of the spinning tool at the sensors on +x and +y:
//   c_x = e sin(theta_1 + a) + sum_h A_h cos(h (pi / 2 - theta_1) + phi_h),
//   c_y = e cos(theta_1 + a) + sum_h A_h cos(-h theta_1 + phi_h),        h = 2, 3, ...
// (eccentricity e at angle a; out-of-roundness harmonics of amplitude A_h, phase phi_h), m.
struct ToolContour {
  double eccentricity_m = 0.0;
  double eccentricity_angle_rad = 0.0;
  std::vector<double> harmonic_m;          // A_2, A_3, ...
  std::vector<double> harmonic_phase_rad;  // phi_2, phi_3, ... (same size, or empty: drawn)

  double x_m(double theta1_rad) const;  // requires harmonic_phase_rad.size() == harmonic_m.size()
  double y_m(double theta1_rad) const;
};

// Tachometer volts at theta_1 when theta_1 advances 1 / samples_per_rad per sample: high_V for
// width_samples samples after each instant theta_1 = offset (mod 2 pi), 0 V otherwise, with
// two-sample linear ramps centred on the instant (and on its end).
double tach_volts(double theta1_rad, double offset_rad, double samples_per_rad,
                  double width_samples, double high_V = 5.0);

// Simulator steps per tooth pass for a record sampled P times a revolution: the smallest S that
// is a multiple of P (every S / P-th step is a sample) and of the teeth (a whole number of steps
// per tooth pass) with S >= min_steps_per_tooth teeth (000 sec. 5.2: 800); returns S / teeth.
// @throws InputError unless samples_per_revolution >= 1, teeth >= 1, min_steps_per_tooth >= 1
int sampled_steps_per_tooth(int samples_per_revolution, int teeth, int min_steps_per_tooth = 800);

struct CutRecordSpec {
  // Tool, modal parameters, per-tooth coefficients, cut conditions and depth profile of the
  // cut; teeth * steps_per_tooth must be a multiple of P (sampled_steps_per_tooth).
  milling::SimulationOptions cut;
  double fs_hz = 100000.0;               // sample rate, Hz; fs 60 / rpm a whole number >= 16
  int air_revolutions = 12;              // spinning before the cut, >= 0
  int tail_revolutions = 2;              // spinning after it, >= 0
  double offset_angle_deg = 0;           // theta_1 at the tachometer's rising edge, deg
  double noise_tip_m = 5e-7;             // white noise std at the tip, m, >= 0 (000 sec. 6.1)
  double sensor_to_tip = 2.78;           // tip deflection / sensor deflection, > 0 (000 sec. 3.1)
  ToolContour contour;                   // at the sensors
  double tach_width_revolutions = 0.05;  // pulse length, in (0, 1)
  double tach_high_V = 5.0;
  std::uint64_t seed = 1;
};

struct CutRecord {
  StepSummary summary;  // fails with "simulation failed: <why>" when the run diverged
  Eigen::VectorXd x_sensor_m, y_sensor_m;  // at the sensors, m
  Eigen::VectorXd tach_V;
  Eigen::VectorXd x_tip_m, y_tip_m;        // true tip deflection (no noise, no contour)
  Eigen::VectorXd theta1_rad;              // true theta_1, unwrapped (0 at sample 0)
  std::vector<double> harmonic_phase_rad;  // the contour's phases as used
  int samples_per_revolution = 0;          // P
  int cut_revolutions = 0;                 // the simulated run's revolutions
  // Record time (t = i / fs): the air window written for the contour (air_revolutions - 1
  // revolutions from 0) and the cut window, s.
  double air_start_s = 0.0, air_end_s = 0.0;
  double cut_start_s = 0.0, cut_end_s = 0.0;
  double depth_start_m = 0.0, depth_end_m = 0.0;  // simulated depth at the cut's ends
};

// The record above.
// @throws InputError naming the field for a spec that breaks its rules (and as
//         milling::simulate for invalid simulator options)
CutRecord synthesize_cut_record(const CutRecordSpec& spec);

}  // namespace sync
}  // namespace chatterlab
