// Bifurcation detection on once-per-revolution samples (000 secs 5.2-5.3): where a run passes
// between the chatter-free period-one orbit and chatter, and the bifurcation depth by the
// results format's rule (EXPERIMENT_FORMAT.md, bifurcation_depth_mm). docs/bifurcation.md.
//
// Criterion (options in bifurcation_options.h):
//  1. s_n, the robust local spread of x_n about a local quadratic trend over W revolutions
//     (local_spread.h): ~ sigma on a noisy period-one orbit whatever its slow drift, ~ A on
//     chatter of amplitude A (clusters, ellipse or cloud).
//  2. The noise floor sigma_0: measurement_noise_m if stated, else the noise_quantile quantile
//     of the robust std of the standardised central residuals over blocks of
//     noise_block_revolutions; never below min_noise_floor_m.
//  3. Hysteresis: chatter is confirmed by min_chatter_revolutions consecutive revolutions
//     with s_n > enter_factor sigma_0; the episode reaches back from there and forward to the
//     revolutions where s_n falls to exit_factor sigma_0, and ends at a quiet stretch
//     (s_n <= exit_factor sigma_0) of min_stable_revolutions or one that reaches the run's end;
//     shorter quiet stretches are bridged.
//  4. Transitions are the revolutions where the state changes; the bifurcation depth is the
//     depth of the first onset of an incline, of the last end of chatter of a decline, none
//     for a constant-depth run, and none when the state never changes.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/dynamics/bifurcation_options.h"

namespace chatterlab {
namespace dynamics {

enum class RevolutionState : unsigned char { kStable, kChatter };

// Direction of the depth over the run (BifurcationOptions::constant_depth_tolerance_m).
enum class DepthProfile { kIncline, kDecline, kConstant };

// What the run did as a whole.
enum class RunVerdict { kAllStable, kAllChatter, kChanges };

enum class NoiseFloorSource { kStated, kQuietestBlocks, kMinimum };

enum class TransitionKind { kOnset, kEnd };

// A change of state: `revolution` is the first revolution in the new state.
struct Transition {
  Eigen::Index revolution = 0;
  double depth_m = 0.0;  // depth_m[revolution]
  TransitionKind kind = TransitionKind::kOnset;
};

// Chatter that starts and ends within the run (000 Fig. 5.15): revolutions
// [onset_revolution, end_revolution) chatter, the ones before and after do not.
struct ChatterIsland {
  Eigen::Index onset_revolution = 0;
  Eigen::Index end_revolution = 0;
  double onset_depth_m = 0.0;  // depth_m[onset_revolution]
  double end_depth_m = 0.0;    // depth_m[end_revolution]
};

struct BifurcationResult {
  StepSummary summary;  // default: not run
  DepthProfile profile = DepthProfile::kConstant;
  RunVerdict verdict = RunVerdict::kAllStable;
  // Incline: depth of the first onset; decline: depth of the last end of chatter. Empty for a
  // constant-depth run (the format leaves the key out), when the state never changes (the
  // format's null) and when the run changes state without the transition its direction asks
  // for (a warning says so).
  std::optional<double> bifurcation_depth_m;
  std::vector<Transition> transitions;  // in revolution order
  std::vector<ChatterIsland> islands;
  std::vector<RevolutionState> state;  // one per revolution
  Eigen::VectorXd spread_m;            // s_n, one per revolution
  double noise_floor_m = std::numeric_limits<double>::quiet_NaN();
  NoiseFloorSource noise_floor_source = NoiseFloorSource::kMinimum;
  double enter_threshold_m = std::numeric_limits<double>::quiet_NaN();
  double exit_threshold_m = std::numeric_limits<double>::quiet_NaN();
  double chatter_fraction = std::numeric_limits<double>::quiet_NaN();  // of the revolutions
};

// @param depth_m  axial depth at each once-per-revolution sample (m), finite
// @param x_m      the once-per-revolution samples x_n (m), finite, same size as depth_m
// @return summary.ok() unless the run is shorter than options.window_revolutions revolutions
// @throws InputError on invalid options, different sizes or non-finite values
BifurcationResult detect_bifurcation(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                     const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                     const BifurcationOptions& options = {});

// Several lines for a log or a report: profile, verdict, floor and thresholds, transitions and
// islands (depths in mm), the bifurcation depth, warnings.
std::string full_report(const BifurcationResult& result);

const char* to_string(DepthProfile profile);
const char* to_string(RunVerdict verdict);
const char* to_string(NoiseFloorSource source);
const char* to_string(TransitionKind kind);

}  // namespace dynamics
}  // namespace chatterlab
