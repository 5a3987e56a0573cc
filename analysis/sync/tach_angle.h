// Tool angle from the once-per-revolution laser tachometer (000 sec. 3.1).
//
// Rising edges e_0 < e_1 < ... (fractional sample indices, signal::rising_edges) bound the
// tachometer revolutions: revolution k runs from e_k to e_(k+1). The tach phase of sample i is
//   phi(i) = 2 pi k + 2 pi (i - e_k) / (e_(k+1) - e_k),        e_k <= i < e_(k+1),
// linear between edges, so a slowly drifting speed is followed revolution by revolution.
// Before e_0 and after the last edge phi is extrapolated at the rate of the neighbouring
// revolution. phi is unwrapped (2 pi k at edge k, negative before e_0).
//
// The offset angle (EXPERIMENT_FORMAT.md, kind: cut; 000 sec. 5.1) is the value of theta_1 at
// every rising edge, so
//   theta_1(i) = phi(i) + offset.
// It is unknown until offset_angle.h finds it: every step before works on phi.
//
// Time origin: sample i is at t = i / fs (t = 0 at the first sample of the record).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/sync/sync_options.h"

namespace chatterlab {
namespace sync {

struct TachAngle {
  StepSummary summary;
  double fs_hz = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> edges;  // rising edges, fractional sample indices, increasing
  // Unwrapped tach phase phi of every sample, rad (see above). Empty unless summary.ok().
  Eigen::VectorXd phase_rad;
  int revolutions = 0;  // whole tachometer revolutions: edges.size() - 1
  // Mean speed over the whole revolutions, 60 fs revolutions / (e_last - e_0); and the
  // slowest and fastest single revolution, rpm.
  double measured_rpm = std::numeric_limits<double>::quiet_NaN();
  double min_rpm = std::numeric_limits<double>::quiet_NaN();
  double max_rpm = std::numeric_limits<double>::quiet_NaN();
  double expected_rpm = std::numeric_limits<double>::quiet_NaN();  // spindle_rpm given
  // Levels and detector settings used, V.
  double low_V = std::numeric_limits<double>::quiet_NaN();
  double high_V = std::numeric_limits<double>::quiet_NaN();
  double threshold_V = std::numeric_limits<double>::quiet_NaN();
  double hysteresis_V = std::numeric_limits<double>::quiet_NaN();
};

// Edges, phase and speed of a tachometer channel.
//
// Levels: low and high are the medians of the finite samples below and at/above the
// mid-range (min + max) / 2; they fix the default threshold (their midpoint) and the
// hysteresis (options.hysteresis_fraction (high - low)).
//
// Data problems fail the summary (ok = false) with a message naming the measured values: a
// flat or all-NaN channel, no rising edge, a single edge (no revolution to measure), an edge
// interval more than options.rpm_tolerance from 60 fs / spindle_rpm samples (the first such
// revolution, its time, measured and expected rpm).
//
// @param tach_V       tachometer channel after its calibration, V; any length
// @param fs_hz        sample rate, Hz, > 0
// @param spindle_rpm  nominal speed (test.yaml spindle_rpm), > 0
// @throws InputError for fs_hz, spindle_rpm or options that break their rules
TachAngle tach_angle(const Eigen::Ref<const Eigen::VectorXd>& tach_V, double fs_hz,
                     double spindle_rpm, const TachOptions& options = {});

// phi wrapped to [0, 2 pi).
double wrap_phase_rad(double phase_rad);

// theta_1 of every sample, rad in [0, 2 pi), for a given offset angle: wrap(phi + offset).
Eigen::VectorXd theta1_rad(const TachAngle& tach, double offset_angle_deg);

// theta_1 of every sample, increasing: theta1_rad(tach, offset) unwrapped
// (signal::unwrap_phase_rad), starting in [0, 2 pi) at sample 0. For sampling once per
// revolution at a fixed theta_1 (dynamics/revolution_sampling.h).
Eigen::VectorXd theta1_unwrapped_rad(const TachAngle& tach, double offset_angle_deg);

}  // namespace sync
}  // namespace chatterlab
