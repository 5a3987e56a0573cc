// Synthetic rotating-dynamometer record of a two-tooth full-immersion slot (000 sec. 3.2),
// for tests and for the program's synthetic campaigns.
//
// Model. Tooth 1 is at theta(t) = theta_0 + Omega t, tooth 2 at theta + pi (000 ch. 2
// conventions); each cuts for its angle in [0, pi) with chip h sin(theta_p) and forces
// F_t, F_r of 000 eqs 3.3-3.4 (analysis/milling/force_model.h), so one tooth cuts at a time.
// The dynamometer axes rotate with the tool at theta_dyn to the teeth, consistent with
// 000 eqs 3.1-3.2:
//   [Fx; Fy] = s_p (F_t [cos theta_dyn; sin theta_dyn] + F_r [-sin theta_dyn; cos theta_dyn]),
// with s_1 = +1, s_2 = -1 (tooth 2 is tooth 1 turned by pi). The zero-count pulse leads the
// tooth change at theta = 0 (mod pi) by theta_dyn (000 sec. 3.2 sign convention: positive when
// the zero-count occurs before the intersection): its 50 % rising level is at the instants
// where theta = -theta_dyn (mod 2 pi). The rising and falling edges are linear ramps of
// zero_pulse_rise_s; with a ramp of at least two samples, linear interpolation at half
// amplitude returns the pulse instant exactly (a sampled step would be off by up to 1/2
// sample).
//
// Channel offsets and white Gaussian noise from a generator seeded with `seed` are added.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "analysis/milling/force_model.h"

namespace chatterlab {
namespace cutting {

struct SlotRecordSpec {
  double spindle_rpm = 9000.0;                // spindle speed, rev/min, > 0
  double feed_per_tooth_m = 0.1e-3;           // h, m, >= 0
  double depth_m = 1.0e-3;                    // axial depth b, m, > 0
  milling::CuttingCoefficients coefficients;  // no default: must be set
  double theta_dyn_rad = 0.0;                 // dynamometer angle to the teeth (000 eqs 3.1-3.2)
  double initial_tool_angle_rad = 0.0;        // theta_0: tooth-1 angle at t = 0
  double offset_x_N = 0.0;                    // constant added to Fx (conditioner offset), N
  double offset_y_N = 0.0;                    // constant added to Fy, N
  double noise_std_N = 0.0;                   // white Gaussian noise on Fx and Fy, N, >= 0
  double zero_noise_std_V = 0.0;              // white Gaussian noise on the zero channel, V, >= 0
  double zero_pulse_amplitude_V = 5.0;        // zero-count pulse high level (low level is 0 V)
  double zero_pulse_width_s = 2.0e-4;         // time at the high level, s, > 0
  double zero_pulse_rise_s = 5.0e-5;          // duration of each edge ramp, s, > 0
  double fs_hz = 50000.0;                     // sampling rate, Hz, > 0
  double duration_s = 0.5;                    // record length, s (floor(duration * fs) samples)
  std::uint64_t seed = 1;                     // seed of the local noise generator
};

struct SlotRecord {
  Eigen::VectorXd Fx_N;    // force along the rotating dynamometer x axis, N
  Eigen::VectorXd Fy_N;    // force along the rotating dynamometer y axis, N
  Eigen::VectorXd zero_V;  // zero-count channel, V
  double fs_hz = 0.0;
  // Truth for tests: instants (s) of the zero-count pulses' 50 % rising level inside the
  // record, and of the tooth changes (theta = 0 mod pi).
  std::vector<double> zero_count_times_s;
  std::vector<double> tooth_change_times_s;
};

// Throws InputError naming the first field of `spec` that breaks its rule.
SlotRecord generate_slot_record(const SlotRecordSpec& spec);

}  // namespace cutting
}  // namespace chatterlab
