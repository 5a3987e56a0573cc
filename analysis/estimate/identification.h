// The identification sequence of a cut test (000 sec. 5.1; docs/identification.md, "Sequence"),
// iterated to a fixed point. Each pass, with the offset angle delta_i and the known modal values
// M_i (pass 1: the hammer test's, and the offset found with them and the dynamometer's):
//   1. ekf-coeff-xy-per-tooth with M_i known, every tooth starting at the dynamometer Kt, Kr:
//      per-tooth coefficients K_i;
//   2. ekf-modal-xy-mk then ekf-modal-xy-mc with K_i known (modal_sequence.h, one pass), both
//      starting at the hammer m, k; mk holds the damping at the previous pass's c (pass 1: the
//      hammer's): identified m, c, k = M_(i+1);
//   3. the offset angle found again (sync/offset_angle.h) over the measured mean revolution with
//      M_(i+1) on both axes and K_i: delta_(i+1).
// Passes stop when delta moves by less than offset_tolerance_deg and every parameter by less
// than parameter_tolerance (relative) from one pass to the next, or after max_passes (1: 000
// sec. 5.1 as written).
#pragma once

#include <limits>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/ekf_options.h"
#include "analysis/estimate/tool_model.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/revolution_mean.h"

namespace chatterlab {
namespace estimate {

// Defaults: docs/identification.md.
struct IdentificationOptions {
  int max_passes = 8;                  // identification passes, >= 1 (1: 000 sec. 5.1 as written)
  double offset_tolerance_deg = 0.05;  // passes stop when the offset moves less than this, >= 0
  double parameter_tolerance = 0.005;  // ... and every parameter by less than this fraction, >= 0
  ModalEkfOptions modal;               // steps 2 (and the modal variants after)
  CoeffEkfOptions coeff;               // step 1 (and the coefficient variants after)
};

// What the sequence starts from (000 sec. 5.1).
struct IdentificationInputs {
  CutSetup setup;  // the cut as the filters model it
  // Tool and cut conditions of the simulated revolution of step 3; its modal_x, modal_y and
  // coefficients are replaced by each pass's values (no edge terms, 000 sec. 5.1).
  milling::SimulationOptions cut_model;
  double initial_offset_deg = std::numeric_limits<double>::quiet_NaN();  // delta_1, deg
  double offset_depth_m = std::numeric_limits<double>::quiet_NaN();      // step 3's depth, m, > 0
  ModalParameters hammer;         // hammer-test m, c, k: M_1, and every modal run's start
  ToothCoefficients dynamometer;  // dynamometer Kt, Kr: every tooth's start in step 1
};

struct IdentificationPass {
  double offset_deg = 0.0;                      // delta_i, the offset the pass ran with
  std::vector<ToothCoefficients> coefficients;  // K_i
  ModalParameters modal;                        // M_(i+1)
  double offset_after_deg = 0.0;                // delta_(i+1)
  double offset_relative_error = 0.0;           // step 3's relative error
};

struct IdentificationResult {
  StepSummary summary;  // ok when every pass ran; warns when the passes did not settle
  std::vector<IdentificationPass> passes;  // the passes run (also those before a failure)
  bool converged = false;                  // the last pass settled against the one before
  // Identified values (the last pass): m, c, k equal on x and y (000 sec. 5.1) and Kt_p, Kr_p.
  ModalParameters modal;
  std::vector<ToothCoefficients> coefficients;
  sync::OffsetAngleResult offset;  // found with the identified values (the last step 3)
};

// The pass-to-pass test above: |delta(now) - delta(before)| (the shorter way round the circle)
// < offset_tolerance_deg and |p(now) - p(before)| / |p(before)| < parameter_tolerance for p in
// m, c, k and every Kt_p, Kr_p (both passes with the same number of teeth).
bool passes_settled(const IdentificationPass& now, const IdentificationPass& before,
                    const IdentificationOptions& options);

// Runs the sequence above on a window resampled with theta_1 = the tachometer phase (offset 0,
// window_samples, then resample_cut); each pass adds its offset (with_offset_angle).
// @param measured_mean  the measured mean revolution the offset angle is found against
// @throws InputError for options that break their rules ("identification.max_passes = 0: must
//         be >= 1"). A step that fails or throws on the data ends the sequence in summary (the
//         pass and step named, or the error's message), keeping the passes before it.
IdentificationResult identify_cut(const MeasuredCut& window,
                                  const sync::RevolutionMean& measured_mean,
                                  const IdentificationInputs& inputs,
                                  const IdentificationOptions& options = {});

}  // namespace estimate
}  // namespace chatterlab
