// The cut-test step (DESIGN.md data flow, 000 sec. 3.1 and 5.1): tachometer angle, runout
// contour removed (air window), tip deflection, offset angle from a simulated revolution with
// the campaign's hammer-test modal parameters and dynamometer coefficients, and for ramped
// cuts the measured bifurcation depth; then the identification sequence and the estimator
// variants (cut_estimation.h).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/dynamics/bifurcation.h"
#include "analysis/dynamics/poincare.h"
#include "analysis/frf/mode.h"
#include "analysis/milling/force_model.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/revolution_mean.h"
#include "analysis/sync/tach_angle.h"
#include "app/core/campaign.h"
#include "app/kinds/cut/cut_estimation.h"
#include "app/kinds/cut/cut_spec.h"
#include "app/pipeline/outcome.h"

namespace chatterlab::app {

// Campaign values the cut step takes from the other tests (000 sec. 5.1: hammer-test modal
// parameters and dynamometer coefficients). Unset: that step of the cut analysis is skipped
// with the reason.
struct CutStepInputs {
  std::optional<frf::Mode> hammer_x, hammer_y;  // first mode of tap/x and tap/y (x for y when
                                                // only x was tapped)
  std::string hammer_source;                    // test ids, for the report
  std::optional<milling::CuttingCoefficients> coefficients;  // dyno group
  std::optional<ToolSpec> tool;
};

struct CutOutcome : KindResult {
  StepSummary summary;  // ok when the tachometer angle and the tip deflection exist
  std::vector<std::string> warnings;
  sync::TachAngle tach;  // phase of every sample, measured speed
  sync::RevolutionMean contour;
  int air_revolutions = 0;
  // A few revolutions of the cut for the figure: time, raw tip deflection (sensor x
  // sensor_to_tip, contour in) and processed x.
  Eigen::VectorXd excerpt_t_s, excerpt_raw_x_m, excerpt_x_m;

  StepSummary offset_status;             // "not run" until the offset angle step ran
  sync::OffsetAngleResult offset;        // with the hammer-test and dynamometer values
  sync::RevolutionMean offset_measured;  // the measured mean revolution it compared with

  StepSummary bifurcation_status;  // ramped cuts only
  bool ramped = false;
  // Constant-depth cuts: stable or chatter by the Poincare class of the map centred on the
  // middle revolution of the cut window (a fixed point: stable), judged against the noise floor
  // of the bifurcation criterion (docs/lobes.md "Measured points").
  StepSummary orbit_status;
  dynamics::OrbitClass orbit;
  double orbit_noise_floor_m = 0.0;
  Eigen::VectorXd depth_n_m, x_n_m;  // once-per-revolution samples at theta_1 = 0 in the cut
  dynamics::BifurcationResult bifurcation;
  std::vector<dynamics::PoincareMap> poincare;
  double detector_noise_m = 0.0;  // measurement noise the detector used

  CutEstimation estimation;  // summary "not run" when the step did not run
};

struct CutStepOptions {
  EstimationOptions estimation;
  std::vector<std::string> estimation_errors;  // campaign.yaml estimation: problems
  int jobs = 1;                                // threads for the estimator variants
};

// The problems of a cut test's windows (cut_window_s, air_window_s, estimation_window_s) against
// a record of duration_s seconds, one message each naming the file and key: a window must lie
// in 0 .. duration_s and end after it starts. Empty: every window is inside the record. The
// kind's check_record (which `validate` and `report` both run) and run_cut_test use it.
std::vector<std::string> cut_window_errors(const TestSpec& t, double duration_s);

// A window bound as the messages print it: %g (-0.5, 7.5, -1e+06, nan, inf).
std::string window_text(double s);

// A test whose windows are not inside its record fails with cut_window_errors' messages.
CutOutcome run_cut_test(const TestSpec& t, const CutStepInputs& inputs,
                        const CutStepOptions& options = {});

}  // namespace chatterlab::app
