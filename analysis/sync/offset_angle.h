// The offset angle of a cut run (000 sec. 5.1): the value of theta_1 at the rising tachometer
// edge (EXPERIMENT_FORMAT.md, kind: cut), found by simulating one steady revolution with a
// parameter set (000: hammer-test modal parameters and dynamometer coefficients) and shifting
// the measured mean revolution against it (offset_search.h).
//
//   1. comparison_window: whole revolutions at (near) constant depth -- the last revolutions of
//      a constant-depth cut, or those around a chosen depth of a ramp;
//   2. mean_revolution (revolution_mean.h) of the processed tip deflection over that window;
//   3. find_offset_angle: simulate from rest at the window's depth for
//      options.simulated_revolutions, keep the last revolution (theta_1 known per step), search
//      every candidate offset, refine, and return the synchronized revolution (000 figs
//      5.9-5.14: simulated and measured x, y against theta_1).
//
// With n alike teeth the steady revolution repeats every 360 / n deg and the offset is only
// defined modulo 360 / n: the search reports the runner-up minimum and flags the result
// ambiguous when it fits almost as well (OffsetSearchOptions::ambiguity_ratio).
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/cut_schedule.h"
#include "analysis/sync/offset_search.h"
#include "analysis/sync/revolution_mean.h"
#include "analysis/sync/sync_options.h"

namespace chatterlab {
namespace sync {

struct ComparisonWindow {
  double start_s = std::numeric_limits<double>::quiet_NaN();
  double end_s = std::numeric_limits<double>::quiet_NaN();
  double depth_m = std::numeric_limits<double>::quiet_NaN();  // depth at the window's centre
};

// Time window of revolutions + 1 nominal revolutions (60 / spindle_rpm each), so that at least
// `revolutions` whole tachometer revolutions fall inside at the nominal speed:
//  - constant depth: ending one nominal revolution before cut_end_s (the most settled
//    revolutions, clear of the exit); depth_m is ignored;
//  - ramp: centred on the instant where the depth passes depth_m, shifted to stay one nominal
//    revolution inside the cut window.
// @throws InputError if the schedule is not finite or not increasing in time, revolutions < 1,
//         the window does not fit inside the cut window, or (ramp) depth_m is not within the
//         ramp's depths
ComparisonWindow comparison_window(const CutSchedule& cut, double spindle_rpm, int revolutions,
                                   double depth_m = std::numeric_limits<double>::quiet_NaN());

struct OffsetAngleResult {
  StepSummary summary;
  OffsetSearch search;  // offset_angle_deg, rms_error_m, error curve, runner-up, ambiguous
  // Every tooth of the parameter set has the same coefficients: E(delta) then repeats every
  // 360 / n deg (up to the settle change) and the runner-up ties; when it does (ambiguous),
  // offset_angle_deg is reported in [0, 360 / n) (EXPERIMENT_FORMAT.md: defined modulo
  // 360 / n).
  bool model_teeth_alike = false;
  // search.rms_error_m / RMS of the measured revolution (both axes): 0 for a perfect match.
  double relative_error = std::numeric_limits<double>::quiet_NaN();
  double depth_m = std::numeric_limits<double>::quiet_NaN();  // simulated depth
  RevolutionRange measured_revolutions;                       // the measured mean's revolutions
  // Synchronized revolution (000 figs 5.9-5.14) on theta_1 = 360 j / N deg (N: the measured
  // grid): the simulation at theta_1 and the measurement at tach phase theta_1 - offset.
  Eigen::VectorXd theta1_deg;
  Eigen::VectorXd simulated_x_m, simulated_y_m;
  Eigen::VectorXd measured_x_m, measured_y_m;
  // RMS difference of the last two simulated revolutions / RMS of the last one.
  double settle_change = std::numeric_limits<double>::quiet_NaN();
  int simulated_revolutions = 0;
  double simulation_runtime_s = 0.0;  // wall time of the simulation
  double search_runtime_s = 0.0;      // wall time of the candidate search and refinement
};

// Steps 3 above. `parameters` carries the tool, modal parameters, per-tooth coefficients and
// cut conditions (its depth profile is replaced by a constant depth_m for
// options.simulated_revolutions). The summary fails if the simulation diverges; it warns when
// the result is ambiguous or the simulation has not settled.
// @param measured  mean revolution of the processed tip deflection (mean_revolution)
// @param depth_m   axial depth of the comparison window, m, > 0
// @throws InputError for invalid parameters (milling::validate), depth or options
OffsetAngleResult find_offset_angle(const RevolutionMean& measured,
                                    const milling::SimulationOptions& parameters, double depth_m,
                                    const OffsetSearchOptions& options = {});

}  // namespace sync
}  // namespace chatterlab
