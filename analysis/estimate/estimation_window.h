// The estimation window of a cut test (docs/identification.md, "Window"): the stretch of
// chatter-free cutting the filters of 000 ch. 4 run over (000 sec. 6.2: 0.2 s), and its samples.
//
// Rule, with T = 60 / rpm (one revolution) and tau = T / n (the chip delay: the filters start
// one delay into the window, so the window is window_s + tau long):
//  - a window given by test.yaml (estimation_window_s) is used as it is;
//  - constant depth: the window ends one revolution before the cut ends (the most settled
//    cutting);
//  - ramp: centred where the depth is 3/4 of the measured bifurcation depth (chatter-free
//    cutting, as deep as it stays chatter-free); near the shallow end (1/4 of the depth range)
//    when the run chatters throughout (with a warning: the filters assume chatter-free
//    cutting); at 3/4 of the deepest depth when no bifurcation was measured;
//  - never earlier than settle_revolutions after the cut starts, never later than one
//    revolution before it ends (a shorter window then warns).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/dynamics/bifurcation.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/sync/cut_schedule.h"

namespace chatterlab {
namespace estimate {

struct EstimationWindowOptions {
  double window_s = 0.2;             // data the filters run over, s, > 0 (000 sec. 6.2: 0.2 s)
  double settle_revolutions = 20.0;  // revolutions after the cut starts that are never used, >= 0
};

struct EstimationWindow {
  double start_s = 0.0, end_s = 0.0;  // record time; the filters start one chip delay later
  double depth_start_m = 0.0, depth_end_m = 0.0;  // the schedule's depth at start_s, end_s
  std::string rule;                               // how it was chosen, for the report
  std::vector<std::string> warnings;              // a shortened window, a run that chatters
};

// The rule above.
// @param cut                 the cut's schedule (cut_window_s, axial depths)
// @param spindle_rpm         nominal speed, > 0
// @param teeth               n, >= 1 (the chip delay tau = 60 / (rpm n))
// @param given_s             test.yaml estimation_window_s, if given
// @param measured            the measured bifurcation of a ramped cut, or null (none measured)
// @throws InputError "estimation window <start> to <end> s: the filters need at least four
//         revolutions of settled cutting (after <settle> settling revolutions)" when the window
//         spans four revolutions or less; for spindle_rpm, teeth or options that break their
//         rules
EstimationWindow choose_estimation_window(const sync::CutSchedule& cut, double spindle_rpm,
                                          int teeth,
                                          const std::optional<std::pair<double, double>>& given_s,
                                          const dynamics::BifurcationResult* measured,
                                          const EstimationWindowOptions& options = {});

// The window's samples of a record sampled at fs_hz, from the first sample at or after start_s
// to the last at or before end_s (or the record's end), at the record's step 1 / fs_hz (the
// filters take them after resample_cut to their step, 000 sec. 6.1): tip deflections, theta_1
// and the schedule's depth at each sample (one value at constant depth). theta_1 is taken as
// given: normally the tachometer phase with offset 0, to which each offset adds
// (with_offset_angle).
// @param x_m, y_m, theta1_rad  the whole record, same length
// @throws InputError "estimation window <start> to <end> s lies outside the record" when it
//         holds fewer than 9 samples of the record; for fs_hz <= 0 or different lengths
MeasuredCut window_samples(const Eigen::Ref<const Eigen::VectorXd>& x_m,
                           const Eigen::Ref<const Eigen::VectorXd>& y_m,
                           const Eigen::Ref<const Eigen::VectorXd>& theta1_rad, double fs_hz,
                           const sync::CutSchedule& cut, const EstimationWindow& window);

}  // namespace estimate
}  // namespace chatterlab
