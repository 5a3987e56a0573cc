// The estimation part of a cut test (000 secs 5.1, 5.3, ch. 6; docs/identification.md):
//
//   1. an estimation window of chatter-free cutting (0.2 s by default, 000 sec. 6.2), its tip
//      deflections and theta_1 resampled by cubic spline to 5e-7 s (000 sec. 6.1);
//   2. the identification sequence of 000 sec. 5.1: with the offset angle found from the
//      hammer-test and dynamometer values, ekf-coeff-xy-per-tooth with the hammer modal
//      parameters known; then ekf-modal-xy-mk (damping held at the hammer value) and
//      ekf-modal-xy-mc (stiffness held at the new estimate) with the new coefficients known;
//      then the offset angle found again with the identified values. Further passes repeat the
//      sequence with the previous pass's values as the known ones until the offset and every
//      parameter settle (EstimationOptions::max_passes, tolerances below);
//   3. every estimator variant of EXPERIMENT_FORMAT.md run once more on the final offset with
//      the identified values as the known ones, each with its observability rank at the
//      window's operating point (000 eq. 4.33) and its repeatability over seeded starts within
//      +-50 % of the reference (000 figs 6.19-6.20);
//   4. for ramped cuts, the same cut simulated with the identified values (traditional and
//      numerical chip models), whose bifurcation depth stands beside the measured one
//      (000 table 5.1).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/dynamics/bifurcation.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/estimation_window.h"
#include "analysis/estimate/identification.h"
#include "analysis/estimate/joint_identification.h"
#include "analysis/estimate/modal_sequence.h"
#include "analysis/estimate/observability.h"
#include "analysis/estimate/repeatability.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/offset_angle.h"
#include "analysis/sync/tach_angle.h"
#include "analysis/sync/tip_deflection.h"
#include "app/core/campaign.h"
#include "app/kinds/cut/estimation_options.h"

namespace chatterlab::app {

// The window rule and the identification passes are analysis/estimate's.
using EstimationWindow = estimate::EstimationWindow;
using IdentificationPass = estimate::IdentificationPass;

struct VariantOutcome {
  estimate::EkfResult run;
  StepSummary observability_status;  // not run when the run failed
  estimate::ObservabilityResult observability;
  estimate::RepeatabilityResult repeat;  // summary "not run" when repeat.runs == 0
  // What the run took as known and as its start (for the report's table).
  std::string known, start;
};

struct SimulatedBifurcation {
  std::string chip_model;  // "traditional" | "numerical"
  StepSummary status;
  std::optional<double> depth_m;  // unset: the run never changes state
  dynamics::RunVerdict verdict = dynamics::RunVerdict::kAllStable;
  std::int64_t steps = 0;
  double runtime_s = 0.0;
};

struct CutEstimation {
  StepSummary summary;  // ok when the identification sequence finished
  EstimationWindow window;
  std::int64_t resampled_samples = 0;
  std::vector<IdentificationPass> passes;
  bool converged = false;
  // Identified values (the last pass): m, c, k equal on x and y (000 sec. 5.1) and Kt_p, Kr_p.
  estimate::ModalParameters modal;
  std::vector<estimate::ToothCoefficients> coefficients;
  sync::OffsetAngleResult offset;  // found again with the identified values
  // The joint estimate started from the sequence's values (analysis/estimate/
  // joint_identification.h): reported beside them, with 95 % intervals. Not run when the
  // sequence failed.
  estimate::JointIdentificationResult joint;
  std::vector<VariantOutcome> variants;
  // Chip thickness of every tooth over the first revolutions of the filter window (000 fig.
  // 6.18): t (record time) and one column per tooth, m (0: not cutting).
  Eigen::VectorXd chip_t_s;
  Eigen::MatrixXd chip_m;
  std::vector<SimulatedBifurcation> simulated;  // ramped cuts only
  double runtime_s = 0.0;
};

// m, c, k and every Kt_p, Kr_p under their results.json keys (m_kg, c_kg_s, k_N_m, Kt1_N_m2,
// Kr1_N_m2, ...), in that order: one identification pass's values, or the identified ones.
std::vector<std::pair<std::string, double>> keyed_values(
    const estimate::ModalParameters& modal,
    const std::vector<estimate::ToothCoefficients>& coefficients);

// The combinations of the identified values that tool-deflection data determine without an
// outside scale (docs/identification.md, "Scale"): fn_hz = sqrt(k / m) / 2 pi,
// zeta = c / (2 sqrt(k m)), and per tooth Kt<p>_over_k_per_m = Kt_p / k, Kr<p>_over_k_per_m.
std::vector<std::pair<std::string, double>> scale_free_values(const CutEstimation& e);
std::vector<std::pair<std::string, double>> scale_free_values(
    const estimate::ModalParameters& modal,
    const std::vector<estimate::ToothCoefficients>& coefficients);

// The sequence's identified values by key: keyed_values and scale_free_values of e.modal,
// e.coefficients.
std::map<std::string, double> sequence_values(const CutEstimation& e);

// The cut's identified set, the one the campaign reports and the lobes use
// (docs/identification.md, "Campaign values"): the joint estimate when it succeeded (method
// "joint", every value but k with its 95 % interval), else the sequence's (method "sequence",
// no intervals). values: keyed_values then scale_free_values, lo/hi NaN where there is no
// interval.
struct IdentifiedValue {
  std::string key;
  double value = 0.0;
  double lo = std::numeric_limits<double>::quiet_NaN();
  double hi = std::numeric_limits<double>::quiet_NaN();
};
struct IdentifiedSet {
  std::string method;  // "sequence" | "joint"
  estimate::ModalParameters modal;
  std::vector<estimate::ToothCoefficients> coefficients;
  std::vector<IdentifiedValue> values;
};
IdentifiedSet identified_set(const CutEstimation& e);

// The feedback filter (ekf-coeff-xy-feedback) against the measured-chip per-tooth filter
// (ekf-coeff-xy-per-tooth), per estimate key: 100 (feedback / measured - 1). A measured chip
// carries the sensors' noise in x(t) - x(t - tau), which biases the coefficients low, most on the
// stronger tooth (errors in variables); a feedback value clearly above the measured one there
// shows that bias. Empty unless both ran.
struct FeedbackDifference {
  std::string key;  // "Kt1_N_m2", ...
  double measured = 0.0;
  double feedback = 0.0;
  double difference_pct = 0.0;
};
std::vector<FeedbackDifference> feedback_differences(const CutEstimation& e);

// The joint estimate's values with their 95 % intervals under their results.json keys
// (offset_deg, fn_hz, zeta, m_kg, c_kg_s, Kt1_N_m2, ..., Kt1_over_k_per_m, ...), k_N_m held.
std::vector<std::pair<std::string, const estimate::IntervalValue*>> keyed_intervals(
    const estimate::JointIdentificationResult& j);

struct CutStepInputs;  // cut_step.h

// Steps 1-4 above for one cut test. `initial_offset` is the offset found with the hammer-test
// and dynamometer values over the measured mean revolution `measured_mean`;
// `measured_bifurcation` (ramped cuts, may be null) places the window below the bifurcation;
// detector_noise_m is the measurement noise its detector used, used again on the simulations.
// Never throws: bad input or a failed step ends in summary (and a variant's own summary).
CutEstimation run_cut_estimation(const TestSpec& t, const CutStepInputs& in,
                                 const sync::TachAngle& tach, const sync::TipDeflection& tip,
                                 const sync::RevolutionMean& measured_mean,
                                 const sync::OffsetAngleResult& initial_offset,
                                 const dynamics::BifurcationResult* measured_bifurcation,
                                 double detector_noise_m, const EstimationOptions& options,
                                 int jobs);

// The cut's conditions as the simulator takes them, with the given modal parameters and
// per-tooth coefficients (no edge terms: 000 sec. 5.1).
milling::SimulationOptions cut_model(const TestSpec& t, const ToolSpec& tool,
                                     const milling::AxisModal& x, const milling::AxisModal& y,
                                     const std::vector<milling::CuttingCoefficients>& k);

}  // namespace chatterlab::app
