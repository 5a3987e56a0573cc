// Cuts with known truth for the analysis tests, written by the one cut-record generator
// (analysis/sync/cut_synth.h, also behind `chatterlab synth`), with 000's reference values:
//  - sync tests: whole records (sensors, tachometer) of the 000 sec. 5.2 cut;
//  - estimator tests: the tip deflections acquired at a sampling step with white noise
//    (000 sec. 6.1: 5e-7 m) and resampled by cubic spline to the filter step (000 sec. 6.1:
//    5e-7 s), as a real run is.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/spline_resample.h"
#include "analysis/estimate/tool_model.h"
#include "analysis/milling/simulation.h"
#include "analysis/sync/cut_synth.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/tip_deflection.h"

namespace chatterlab::testing {

// 000 table 5.2, incline trial 1 (the truth of these tests; unequal teeth).
inline estimate::ModalParameters table52_modal() { return {0.03134, 22.21, 9.840e5}; }
inline std::vector<estimate::ToothCoefficients> table52_coefficients() {
  return {{2.483e8, 2.196e8}, {6.641e9, 4.154e9}};
}
// 000 sec. 5.1: the hammer test's values (damping 40 % below the EKF's 22.21 kg/s) and the
// dynamometer's coefficients (alike teeth).
inline estimate::ModalParameters hammer_modal() { return {0.03211, 13.39, 1.023e6}; }
inline estimate::ToothCoefficients dynamometer_coefficients() { return {5.89e8, 3.19e8}; }
// 000 sec. 6.1: the randomized initial estimates used in 000 chs 5-6.
inline estimate::ModalParameters dissertation_start_modal() { return {0.02270, 40.56, 1.162e6}; }
inline std::vector<estimate::ToothCoefficients> dissertation_start_coefficients() {
  return {{1.493e8, 2.315e8}, {4.257e9, 3.106e9}};
}

// The simulator's options for given modal parameters and per-tooth coefficients (no edge
// terms), 000 sec. 5.2's cut conditions otherwise.
inline milling::SimulationOptions cut_options(const estimate::ModalParameters& m,
                                              const std::vector<estimate::ToothCoefficients>& k) {
  milling::SimulationOptions o;
  o.modal_x = m;
  o.coefficients = k;
  return o;
}
inline milling::SimulationOptions table52_incline1() {
  return cut_options(table52_modal(), table52_coefficients());
}
inline milling::SimulationOptions hammer_and_dynamometer() {
  return cut_options(hammer_modal(), {dynamometer_coefficients(), dynamometer_coefficients()});
}

// The sync tests' record: the table 5.2 incline-1 cut at 1 mm for 60 revolutions after 12 air
// revolutions, 100 kHz (400 samples a revolution), offset 147.3 deg, 3 um eccentricity and
// three out-of-roundness harmonics at the sensors, 5e-7 m noise at the tip, sensor_to_tip 2.78.
inline sync::CutRecordSpec sync_test_cut() {
  sync::CutRecordSpec s;
  s.cut = table52_incline1();
  s.cut.depth = milling::DepthProfile::constant(1e-3, 60);
  s.fs_hz = 100000.0;
  s.air_revolutions = 12;
  s.tail_revolutions = 2;
  s.offset_angle_deg = 147.3;
  s.noise_tip_m = 5e-7;
  s.sensor_to_tip = 2.78;
  s.contour.eccentricity_m = 3e-6;
  s.contour.eccentricity_angle_rad = 0.7;
  s.contour.harmonic_m = {0.8e-6, 0.4e-6, 0.2e-6};
  s.contour.harmonic_phase_rad = {0.3, 2.1, 4.0};
  s.seed = 20240611;
  return s;
}

inline sync::CutRecord make_cut(const sync::CutRecordSpec& s) {
  sync::CutRecord r = sync::synthesize_cut_record(s);
  if (!r.summary.ok()) throw std::logic_error(r.summary.message);
  return r;
}

// The estimator tests' cut: constant depth, simulated, acquired, noisy, resampled.
struct SyntheticCutSpec {
  double depth_m = 1e-3;             // constant axial depth
  double record_s = 0.2;             // record handed to the filter (000 sec. 6.1: 0.2 s)
  int settle_revolutions = 30;       // simulated before the record starts (transient decays)
  double acquisition_step_s = 1e-5;  // sampling step of the "sensors" (100 kHz, 000 sec. 6.1)
  double noise_m = 5e-7;             // white measurement noise std (000 sec. 6.1)
  double filter_step_s = 5e-7;       // resampled step (000 sec. 6.1)
  estimate::SplineEnd spline_end = estimate::SplineEnd::kNotAKnot;
  // Simulator steps per tooth pass. 4,000 = 5e-7 s, the filter step: the record is simulated at
  // the resampled step (then acquired at 100 kHz and resampled, as a real run). 000 sec. 5.2's
  // 800 (2.5 us) adds the simulator's own zero-order-hold delay of the force, h / 2, which
  // biases the estimates by up to 1 % (docs/estimators.md).
  int steps_per_tooth = 4000;
  unsigned seed = 20240607;
  estimate::ModalParameters modal = table52_modal();
  std::vector<estimate::ToothCoefficients> coefficients = table52_coefficients();
};

// The record of the generator with no air, no contour and sensor_to_tip 1 (the sensors read
// tip + noise), from the first sample after settle_revolutions, resampled to filter_step_s;
// theta_1 = 0 at that sample (a revolution start, simulation.h).
inline estimate::MeasuredCut synthetic_cut(const SyntheticCutSpec& spec) {
  sync::CutRecordSpec r;
  r.cut = cut_options(spec.modal, spec.coefficients);
  r.cut.steps_per_tooth = spec.steps_per_tooth;
  const milling::SimulationGrid probe = milling::simulation_grid(r.cut);
  const double h = probe.time_step_s;
  const int S = probe.steps_per_revolution;
  const int record_revolutions = static_cast<int>(std::ceil(spec.record_s / (h * S))) + 1;
  r.cut.depth =
      milling::DepthProfile::constant(spec.depth_m, spec.settle_revolutions + record_revolutions);
  r.fs_hz = 1.0 / spec.acquisition_step_s;
  r.air_revolutions = 0;
  r.tail_revolutions = 0;
  r.noise_tip_m = spec.noise_m;
  r.sensor_to_tip = 1.0;
  r.seed = spec.seed;
  const sync::CutRecord rec = make_cut(r);
  const int every = static_cast<int>(std::lround(spec.acquisition_step_s / h));
  const Eigen::Index n = std::llround(spec.record_s / h) / every + 1;
  const Eigen::Index first =
      static_cast<Eigen::Index>(spec.settle_revolutions) * rec.samples_per_revolution;
  estimate::MeasuredCut cut;
  cut.time_step_s = spec.filter_step_s;
  cut.x_m =
      estimate::resample_cubic_spline(rec.x_sensor_m.segment(first, n), spec.acquisition_step_s,
                                      spec.filter_step_s, spec.spline_end);
  cut.y_m =
      estimate::resample_cubic_spline(rec.y_sensor_m.segment(first, n), spec.acquisition_step_s,
                                      spec.filter_step_s, spec.spline_end);
  const double omega = r.cut.spindle_rpm * kRpmToRadPerS;
  cut.theta1_rad = Eigen::VectorXd::LinSpaced(
      cut.x_m.size(), 0.0, omega * spec.filter_step_s * static_cast<double>(cut.x_m.size() - 1));
  cut.depth_m = Eigen::VectorXd::Constant(1, spec.depth_m);
  return cut;
}

// The measured mean revolution of a synthetic record, by the cut chain (tachometer, tip
// deflection, comparison window of the last `revolutions` revolutions of a constant cut, mean
// revolution), and the window's depth. Throws std::logic_error when a step fails.
struct MeasuredRevolution {
  sync::RevolutionMean mean;
  double depth_m = 0.0;
};
inline MeasuredRevolution measured_revolution(const sync::CutRecordSpec& spec,
                                              int revolutions = 20) {
  const sync::CutRecord cut = make_cut(spec);
  const double rpm = spec.cut.spindle_rpm;
  const sync::TachAngle tach = sync::tach_angle(cut.tach_V, spec.fs_hz, rpm);
  if (!tach.summary.ok()) throw std::logic_error("tach: " + tach.summary.message);
  const sync::TipDeflection d = sync::tip_deflection(
      cut.x_sensor_m, cut.y_sensor_m, tach, spec.sensor_to_tip, cut.air_start_s, cut.air_end_s);
  if (!d.summary.ok()) throw std::logic_error("tip deflection: " + d.summary.message);
  const sync::CutSchedule schedule{cut.cut_start_s, cut.cut_end_s, cut.depth_start_m,
                                   cut.depth_end_m};
  const sync::ComparisonWindow w = sync::comparison_window(schedule, rpm, revolutions);
  const sync::RevolutionRange range = sync::whole_revolutions_in(tach, w.start_s, w.end_s);
  if (range.count != revolutions) throw std::logic_error("comparison window: wrong revolutions");
  MeasuredRevolution m;
  m.mean = sync::mean_revolution(d.x_m, d.y_m, tach, range,
                                 sync::contour_phase_points(tach, sync::ContourOptions{}));
  m.depth_m = w.depth_m;
  return m;
}

}  // namespace chatterlab::testing
