// Synthetic records of a spindle-integrated force sensor campaign (notes/003.md section 7,
// format section 6): static load steps, hammer taps on the tool tip and milling cuts, seen
// through a known calibration matrix C and a known tip-to-sensor plant per lateral axis, with
// drift, offsets, unbalance and noise. Signals only (washer newtons, newtons); the file formats
// are app/kinds/sifs/sifs_synth.h's.
//
// Washers from the sensor force (inverse of 003 eq. 3-1 with the Z pair summed, format
// section 6): s = S f_m with S = C^-1, and
//   x1 = a + s_x, x2 = a - s_x, y1 = b - s_y, y2 = b + s_y, z1 = s_z + d, z2 = s_z - d,
// so that s_x = 0.5 (x1 - x2), s_y = -0.5 (y1 - y2), s_z = 0.5 (z1 + z2). The common parts the
// pair signals cancel are a = b = s_z (an axial load presses every washer alike) and
// d = 0.5 s_x (a lateral X load also tilts the Z pair).
//
// Dynamics: the tip force f_a drives the scaled modal plant of 003 eq. 4-27 (sensor_model.h;
// z: G = 1), simulated exactly at a fine rate (oversample x the record rate) for a force held
// over each fine step at its value at the step's midpoint (no half-step delay), then
// anti-aliased and decimated by signal::RationalResampler, as a DAQ with matched channels does
// (the hammer and the dynamometer pass through the same filter).
#pragma once

#include <Eigen/Core>
#include <array>
#include <complex>
#include <cstdint>
#include <vector>

#include "analysis/sifs/calibration.h"
#include "analysis/sifs/sensor_model.h"

namespace chatterlab {
namespace sifs {

// The format's truth example (section 6): rows f_x f_y f_z, columns s_x s_y s_z.
Eigen::Matrix3d default_calibration_matrix();
// notes/003.md section 7: 420 Hz / 0.03 / 0.55, 980 Hz / 0.04 / 0.40, 2400 Hz / 0.05 / 0.05
// (G(0) = 1, antiresonances near 572 and 1970 Hz).
std::vector<SensorMode> default_plant_x();
// The x plant with every frequency 5 % higher (a slightly stiffer Y direction).
std::vector<SensorMode> default_plant_y();

// The washers of the pair signals s (columns s_x s_y s_z), by the rule above.
Washers washers_from_pairs(const Pairs& s);

// Standard deviation of independent white noise of equal variance on the six washers that
// gives calibrated noise of RMS `calibrated_rms_n` on `axis`: var(f_i) = sigma^2 / 2 ||C_i||^2
// (each pair signal has variance sigma^2 / 2).
double washer_noise_for(const Eigen::Matrix3d& C, Axis axis, double calibrated_rms_n);
// The calibrated noise variance on each axis (x, y, z) for washer noise sigma_n.
Eigen::Vector3d calibrated_noise_var(const Eigen::Matrix3d& C, double washer_sigma_n);

// f_m = G * f_a of one axis at the fine rate: u[i] is the force held over [i, i + 1] / fine_hz
// (sample it at (i + 1/2) / fine_hz), y[i] the sensor force at t = i / fine_hz, from rest.
// Exact discretisation of each scaled modal block (exponential of [[A_i, B_i], [0, 0]] T).
// @throws InputError for a mode with fn_hz <= 0, zeta <= 0 or fine_hz <= 0
Eigen::VectorXd simulate_plant(const std::vector<SensorMode>& modes,
                               const Eigen::Ref<const Eigen::VectorXd>& u_held, double fine_hz);

// ---- static test (003 sec. 3.2) ------------------------------------------------------------

struct StaticSynthOptions {
  Eigen::Matrix3d C = default_calibration_matrix();
  double fs_hz = 1024;
  double step_n = 44.482;      // one 10 lb weight
  int steps = 7;               // weights hung one after another, then taken off one by one
  double load_sign = 1.0;      // +1 or -1: the loads' sign along the axis
  double unloaded_s = 10;      // the unloaded windows before the first and after the last load
  double hold_s = 6;           // each load level
  double transition_s = 1;     // linear change between levels (excluded from the windows)
  double settle_s = 0.25;      // also excluded at each end of a window
  double drift_n_per_min = 5;  // each washer drifts linearly at +-(0.5..1) x this (003 table 1)
  double offset_n = 5;         // each washer's offset drawn in [-offset_n, offset_n]
  double noise_n = 0.05;       // white noise std per washer
  std::uint64_t seed = 1;
};

struct StaticSynth {
  Washers washers_n;                            // the record (washer newtons)
  std::vector<LoadWindow> windows;              // levels 0, 1..steps, steps-1..0 (x step_n x sign)
  Eigen::VectorXd load_n;                       // the true load along the axis per sample
  Eigen::Matrix<double, 6, 1> offset_n;         // per washer
  Eigen::Matrix<double, 6, 1> drift_n_per_min;  // per washer
};

// Levels: unloaded, then 1..steps weights, then steps-1..0, each held hold_s (the first and
// last unloaded_s) with transition_s ramps between.
StaticSynth synthesize_static(Axis axis, const StaticSynthOptions& o);

// ---- tap test (003 sec. 4.2.1) -------------------------------------------------------------

struct TapSynthOptions {
  Eigen::Matrix3d C = default_calibration_matrix();
  std::vector<SensorMode> modes;  // the hit axis's plant
  double fs_hz = 12800;
  int oversample = 8;  // fine rate = oversample x fs_hz (51.2 kHz at 4)
  int hits = 5;
  double first_hit_s = 0.1;
  double hit_spacing_s = 0.3;  // nominal, each impact moved by up to +-20 ms
  double window_s = 0.2;       // hit windows: window_s long, from pretrigger_s before impact
  double pretrigger_s = 0.04;
  double peak_min_n = 100, peak_max_n = 300;  // half-sine peaks drawn uniformly
  double pulse_width_s = 5e-4;                // +-20 % per hit
  double cross_fraction = 0.02;  // the other lateral axis sees this x the hit axis's f_m
  double noise_n = 0.15;         // calibrated noise RMS on the hit axis (003: R = 0.15)
  double hammer_noise_n = 0.05;  // white noise std on the hammer channel
  double offset_n = 5;           // washer offsets in [-offset_n, offset_n]
  std::uint64_t seed = 1;
};

struct TapSynth {
  Eigen::VectorXd hammer_n;            // at fs_hz, with noise
  Washers washers_n;                   // at fs_hz
  Eigen::VectorXd sensor_n;            // noise-free f_m on the hit axis at fs_hz (anti-aliased)
  std::vector<double> impact_s;        // pulse starts
  std::vector<double> window_start_s;  // each window [start, start + window_s], on a sample
  double washer_sigma_n = 0.0;
  double noise_var_n2 = 0.0;  // calibrated white noise variance on the hit axis
};

// @throws InputError for a lateral axis other than x or y, or bad options
TapSynth synthesize_tap(Axis axis, const TapSynthOptions& o);

// ---- cut test (003 ch. 4-6) ----------------------------------------------------------------

struct CutForceModel {
  int teeth = 4;
  double radius_m = 9.525e-3;
  double helix_deg = 0.0;  // > 0: the depth is cut in axial_slices discs lagging z tan/r
  int axial_slices = 16;
  bool up_milling = true;
  double radial_immersion_m = 9.525e-3;
  double feed_per_tooth_m = 5e-5;
  double depth_m = 2e-3;
  // 000 eqs 2.1-2.2 with edge terms (3.3-3.4) and the axial force F_a = Kac b h + Kae b.
  double Ktc_N_m2 = 8e8, Krc_N_m2 = 2.4e8, Kte_N_m = 2e4, Kre_N_m = 1.5e4;
  double Kac_N_m2 = 1.6e8, Kae_N_m = 5e3;
  // Radial runout: tooth p stands out rho cos(angle + (p-1) 2 pi / n); chip
  // h_p = fz sin(theta) + rho_p - rho_(p-1) (clipped at 0: no chip, no force).
  double runout_m = 5e-6;
  double runout_angle_deg = 30;
};

struct UnbalanceTerm {
  int h = 1;
  double amp_n = 0.0;
  double phase_deg = 0.0;  // amp cos(h Omega t + phase), t from the record start
};

struct CutSynthOptions {
  Eigen::Matrix3d C = default_calibration_matrix();
  std::vector<SensorMode> plant_x, plant_y;
  CutForceModel force;
  double spindle_rpm = 9000;
  double fs_hz = 12800;
  int oversample = 8;  // even: a truth row is the mean of the oversample held values around it
  double duration_s = 3.5;
  double air_s = 1.0;    // spinning without cutting from 0
  double entry_s = 0.2;  // the engaged depth grows linearly from 0
  double exit_s = 0.2;   // and falls back to 0, ending tail_s before the end
  double tail_s = 0.1;
  double margin_s = 0.05;   // kept off the windows' ends (the plant's transient)
  double theta1_deg = 0.0;  // theta_1 at t = 0
  // Unbalance (003 eq. 3-6 corrected): m0 e Omega^2 at 1x with phase_deg on x, a forward
  // rotating force (y lags x by 90 deg), and h2_fraction of it at 2x with h2_phase_deg.
  double m0e_kg_m = 7.5e-6;
  double unbalance_phase_deg = 40;
  double h2_fraction = 0.1;
  double h2_phase_deg = 110;
  double noise_n = 3.5;          // calibrated noise RMS on x (y, z follow from C)
  double drift_n_per_min = 1.0;  // washers drift at +-(0.5..1) x this
  double offset_n = 5.0;         // washer offsets
  double dyno_angle_deg = 30;    // the dynamometer's x axis, counter-clockwise from machine x
  double dyno_noise_n = 0.3;
  double dyno_offset_n = 5.0;  // each dynamometer channel's offset in [-this, this]
  std::uint64_t seed = 1;
};

struct CutSynth {
  Washers washers_n;                                     // at fs_hz
  Eigen::Matrix<double, Eigen::Dynamic, 3> dyno_n;       // dx dy dz (dynamometer axes)
  Eigen::Matrix<double, Eigen::Dynamic, 3> tip_force_n;  // truth: row k = mean over
                                                         // [k - 1/2, k + 1/2] / fs_hz
  Eigen::Matrix<double, Eigen::Dynamic, 3> sensor_n;     // noise-free G * f_a (anti-aliased)
  std::array<double, 2> air_window_s{};                  // [0.05 s, air_s - margin_s]
  std::array<double, 2> cut_window_s{};  // steady engagement less margin_s at each end
  // Whole revolutions inside cut_window_s, starting on a sample (the truth's window_s).
  std::array<double, 2> harmonic_window_s{};
  std::vector<UnbalanceTerm> unbalance_x, unbalance_y;
  double washer_sigma_n = 0.0;
  Eigen::Vector3d noise_var_n2 = Eigen::Vector3d::Zero();  // calibrated, per axis
};

// @throws InputError for bad options (odd oversample, windows that do not fit, ...)
CutSynth synthesize_cut(const CutSynthOptions& o);

// ---- truth values (format section 6 "truth.yaml") ---------------------------------------

// Local minima of |G(j 2 pi f)| strictly between consecutive mode frequencies (to 1e-3 Hz).
std::vector<double> antiresonances_hz(const std::vector<SensorMode>& modes);
// Lowest f on a 1 Hz grid (1 .. limit_hz) with ||G| - 1| >= 0.1; limit_hz when none (format
// step 7, "before").
double bandwidth_before_hz(const std::vector<SensorMode>& modes, double limit_hz);

}  // namespace sifs
}  // namespace chatterlab
