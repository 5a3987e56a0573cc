// The six EKF estimators of EXPERIMENT_FORMAT.md (000 ch. 4 and 6) and their unscented twins
// run over a measured cut.
//
// Timing (000 eqs 4.5-4.9): the filter starts at sample k0 = CutChips::first_step() (the first
// sample with a delayed sample x(t - tau) in the record) with the initial estimate as x^+_k0
// (deflection and velocity 0, 000 sec. 6.1); step k predicts k -> k + 1 with the force input of
// sample k (chips from the measured x(k), y(k), x(k - tau), y(k - tau), theta_1(k), b(k)) and
// updates with the measured deflection of sample k + 1. steps = N - 1 - k0.
//
//   ekf-modal-x             000 eqs 4.3-4.14: x, xdot, m, c, k; measures x. The force input
//                           (000 eq. 2.3) still needs y for the chip of eq. 2.7.
//   ekf-modal-xy            000 eqs 4.15-4.22: x, xdot, y, ydot, m, c, k; measures x, y.
//   ekf-modal-xy-mk         000 sec. 6.1: ekf-modal-xy without c (rows and columns removed, c
//                           held at inputs.start.c_kg_s).
//   ekf-modal-xy-mc         likewise without k (held at inputs.start.k_N_m).
//   ekf-coeff-xy            000 eqs 4.23-4.32: x, xdot, y, ydot, Kt, Kr with one Kt, Kr for
//                           every tooth.
//   ekf-coeff-xy-per-tooth  000 sec. 4.4: one 6-state filter per tooth (x, xdot, y, ydot,
//                           Kt_p, Kr_p), all stepping together on the same samples. Filter p's
//                           force model takes tooth p's force from its own state and the other
//                           teeth's forces from the other filters' estimates of the previous
//                           sample (a synchronous, order-free coupling). ToothGate (options)
//                           chooses whether filter p corrects Kt_p, Kr_p at every step (kNone,
//                           default) or only while tooth p cuts (kEngaged).
//
//   ukf-modal-x, ukf-modal-xy, ukf-modal-xy-mk, ukf-modal-xy-mc, ukf-coeff-xy,
//   ukf-coeff-xy-per-tooth: the same models, inputs, noise and timing stepped by the
//                           additive-noise unscented filter (unscented_kalman_filter.h). The
//                           coefficient models are linear in their state (the chip is an input),
//                           so there the UKF equals the EKF to rounding. The modal UKFs start
//                           from a physically scaled P0 of the parameters (ModalEkfOptions::
//                           ukf_p0_relative_sd), so that no sigma point has a negative mass.
//
//   ekf-coeff-xy-feedback   000 secs 4.4 and 8.2: ekf-coeff-xy-per-tooth with the chips of each
//                           filter computed from its own estimates, not from the measured
//                           deflections: w = h sin + (x^(t) - x^(t - tau)) sin + (y^ ...) cos,
//                           x^(t) the current estimate (its regenerative stiffness dF/dx enters
//                           the Jacobian) and x^(t - tau) the filter's own estimate one tooth
//                           period earlier, kept for every sample. The delayed estimates enter
//                           as inputs: their cross-covariance with the current state is not
//                           carried (docs/estimators.md, "Feedback variant").
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/ekf_options.h"
#include "analysis/estimate/tool_model.h"
#include "analysis/kalman/consistency.h"

namespace chatterlab {
namespace estimate {

enum class EstimatorId {
  kModalX,
  kModalXy,
  kModalXyMk,
  kModalXyMc,
  kCoeffXy,
  kCoeffXyPerTooth,
  kUkfModalX,
  kUkfModalXy,
  kUkfModalXyMk,
  kUkfModalXyMc,
  kUkfCoeffXy,
  kUkfCoeffXyPerTooth,
  kCoeffXyFeedback,
};

// The filter that steps a variant's model: the EKF of 000 eqs 4.5-4.9, the unscented filter
// of analysis/kalman/unscented_kalman_filter.h on the same model, noise and data, or the EKF
// whose chips come from its own delayed estimates (000 secs 4.4 and 8.2).
enum class FilterKind { kExtended, kUnscented, kExtendedFeedback };

// One row per variant: everything else about the variants (names, state counts, lists of all
// variants, estimate keys) derives from this table.
struct EstimatorInfo {
  EstimatorId id;
  const char* name;   // EXPERIMENT_FORMAT.md
  int states;         // states of one filter
  bool modal;         // estimates modal parameters (ekf_modal) or cutting coefficients (ekf_coeff)
  int measured_axes;  // 1: x; 2: x and y
  bool per_tooth;     // one filter per tooth, keys numbered per tooth ("Kt1_N_m2", ...)
  int key_count;      // estimate keys (per tooth for per_tooth)
  std::array<const char*, 3> keys;  // in EXPERIMENT_FORMAT.md order; per tooth: "Kt", "Kr" stems
  const char* source;               // 000 equations
  FilterKind filter;
  // The EKF variant with the same model (its own id for an EKF): what the variant estimates,
  // from which inputs, is that row's; only the filter differs.
  EstimatorId structure;
};

// clang-format off
inline constexpr std::array<EstimatorInfo, 13> kEstimators{{
//  id, name, states, modal, measured_axes, per_tooth, key_count, keys, source, filter, structure
    {EstimatorId::kModalX,          "ekf-modal-x",            ModalXModel::kStates,    true,  1, false, 3, {"m_kg", "c_kg_s", "k_N_m"},    "000 eqs 4.3-4.14", FilterKind::kExtended, EstimatorId::kModalX},
    {EstimatorId::kModalXy,         "ekf-modal-xy",           ModalXyModel::kStates,   true,  2, false, 3, {"m_kg", "c_kg_s", "k_N_m"},    "000 eqs 4.15-4.22", FilterKind::kExtended, EstimatorId::kModalXy},
    {EstimatorId::kModalXyMk,       "ekf-modal-xy-mk",        ModalXyMkModel::kStates, true,  2, false, 2, {"m_kg", "k_N_m", nullptr},     "000 sec. 6.1 (c held)", FilterKind::kExtended, EstimatorId::kModalXyMk},
    {EstimatorId::kModalXyMc,       "ekf-modal-xy-mc",        ModalXyMcModel::kStates, true,  2, false, 2, {"m_kg", "c_kg_s", nullptr},    "000 sec. 6.1 (k held)", FilterKind::kExtended, EstimatorId::kModalXyMc},
    {EstimatorId::kCoeffXy,         "ekf-coeff-xy",           CoeffXyModel::kStates,   false, 2, false, 2, {"Kt_N_m2", "Kr_N_m2", nullptr}, "000 eqs 4.23-4.32", FilterKind::kExtended, EstimatorId::kCoeffXy},
    {EstimatorId::kCoeffXyPerTooth, "ekf-coeff-xy-per-tooth", CoeffXyModel::kStates,   false, 2, true,  2, {"Kt", "Kr", nullptr},          "000 sec. 4.4", FilterKind::kExtended, EstimatorId::kCoeffXyPerTooth},
    {EstimatorId::kUkfModalX,          "ukf-modal-x",            ModalXModel::kStates,    true,  1, false, 3, {"m_kg", "c_kg_s", "k_N_m"},    "000 eqs 4.3-4.14 model, unscented filter", FilterKind::kUnscented, EstimatorId::kModalX},
    {EstimatorId::kUkfModalXy,         "ukf-modal-xy",           ModalXyModel::kStates,   true,  2, false, 3, {"m_kg", "c_kg_s", "k_N_m"},    "000 eqs 4.15-4.22 model, unscented filter", FilterKind::kUnscented, EstimatorId::kModalXy},
    {EstimatorId::kUkfModalXyMk,       "ukf-modal-xy-mk",        ModalXyMkModel::kStates, true,  2, false, 2, {"m_kg", "k_N_m", nullptr},     "000 sec. 6.1 model (c held), unscented filter", FilterKind::kUnscented, EstimatorId::kModalXyMk},
    {EstimatorId::kUkfModalXyMc,       "ukf-modal-xy-mc",        ModalXyMcModel::kStates, true,  2, false, 2, {"m_kg", "c_kg_s", nullptr},    "000 sec. 6.1 model (k held), unscented filter", FilterKind::kUnscented, EstimatorId::kModalXyMc},
    {EstimatorId::kUkfCoeffXy,         "ukf-coeff-xy",           CoeffXyModel::kStates,   false, 2, false, 2, {"Kt_N_m2", "Kr_N_m2", nullptr}, "000 eqs 4.23-4.32 model, unscented filter", FilterKind::kUnscented, EstimatorId::kCoeffXy},
    {EstimatorId::kUkfCoeffXyPerTooth, "ukf-coeff-xy-per-tooth", CoeffXyModel::kStates,   false, 2, true,  2, {"Kt", "Kr", nullptr},          "000 sec. 4.4 model, unscented filter", FilterKind::kUnscented, EstimatorId::kCoeffXyPerTooth},
    {EstimatorId::kCoeffXyFeedback,    "ekf-coeff-xy-feedback",  CoeffXyModel::kStates,   false, 2, true,  2, {"Kt", "Kr", nullptr},          "000 secs 4.4, 8.2: chips from the filter's delayed estimates", FilterKind::kExtendedFeedback, EstimatorId::kCoeffXyPerTooth},
}};
// clang-format on
inline constexpr std::size_t kEstimatorCount = kEstimators.size();

// The table's row of `id` (rows are in EstimatorId order).
constexpr const EstimatorInfo& estimator_info(EstimatorId id) {
  return kEstimators[static_cast<std::size_t>(id)];
}

// Every variant, in table order.
constexpr std::array<EstimatorId, kEstimatorCount> all_estimators() {
  std::array<EstimatorId, kEstimatorCount> ids{};
  for (std::size_t i = 0; i < kEstimatorCount; ++i) ids[i] = kEstimators[i].id;
  return ids;
}

// "ekf-modal-x", ... (EXPERIMENT_FORMAT.md).
constexpr const char* estimator_name(EstimatorId id) { return estimator_info(id).name; }
// Inverse of estimator_name; throws InputError for an unknown name (listing the known ones).
EstimatorId estimator_from_name(const std::string& name);
// Number of states of one filter of the variant (5, 7, 6, 6, 6, 6, and the same for the UKFs).
constexpr int estimator_states(EstimatorId id) { return estimator_info(id).states; }
constexpr bool is_modal(EstimatorId id) { return estimator_info(id).modal; }
constexpr bool is_unscented(EstimatorId id) {
  return estimator_info(id).filter == FilterKind::kUnscented;
}
// "extended", "unscented" or "extended-feedback" (results.json `filter`).
constexpr const char* filter_name(EstimatorId id) {
  switch (estimator_info(id).filter) {
    case FilterKind::kUnscented:
      return "unscented";
    case FilterKind::kExtendedFeedback:
      return "extended-feedback";
    default:
      return "extended";
  }
}
// The EKF variant with the same model and inputs (the id itself for an EKF).
constexpr EstimatorId structure_of(EstimatorId id) { return estimator_info(id).structure; }
// The variant's estimate keys in EkfResult::estimates order: "m_kg", "c_kg_s", "k_N_m" (modal
// variants without the held one), "Kt_N_m2", "Kr_N_m2", or per tooth "Kt1_N_m2", "Kr1_N_m2",
// "Kt2_N_m2", ... for `teeth` teeth (teeth >= 1; ignored by the other variants).
std::vector<std::string> estimate_keys(EstimatorId id, int teeth = 1);

// Known inputs and initial estimates of the modal filters (000 sec. 6.1).
struct ModalEkfInputs {
  // Known Kt_p, Kr_p of each tooth, one per tooth (000 sec. 6.1: table 5.2's values).
  std::vector<ToothCoefficients> coefficients;
  // Initial estimates of the estimated parameters, and the held value of the others
  // (ekf-modal-xy-mk holds c_kg_s, ekf-modal-xy-mc holds k_N_m). All > 0.
  ModalParameters start;
};

// Known inputs and initial estimates of the coefficient filters (000 sec. 6.2).
struct CoeffEkfInputs {
  ModalParameters modal;  // known m, c, k (equal on x and y), m, k > 0, c >= 0
  // Initial Kt, Kr: one pair (ekf-coeff-xy) or one per tooth (ekf-coeff-xy-per-tooth).
  std::vector<ToothCoefficients> start;
};

// One final parameter estimate under its EXPERIMENT_FORMAT.md key.
struct Estimate {
  std::string key;        // "m_kg", "Kt1_N_m2", ...
  double value = 0.0;     // final estimate
  double variance = 0.0;  // its diagonal entry of the final P^+
};

// States over the run, decimated (options.history_points).
struct EstimateHistory {
  std::vector<std::string> columns;  // "x_m", "vx_m_s", "y_m", "vy_m_s", "m_kg", "Kt1_N_m2", ...
  Eigen::VectorXd time_s;            // sample time from the record's first sample
  Eigen::MatrixXd values;            // time_s.size() x columns.size()
};

struct EkfResult {
  StepSummary summary;  // not run; failed (with the step) if the state became non-finite
  EstimatorId id = EstimatorId::kModalX;
  std::string estimator;            // estimator_name(id)
  std::vector<Estimate> estimates;  // the variant's estimate keys, in EXPERIMENT_FORMAT.md order
  // Final state and the diagonal of its covariance, named as history.columns (per-tooth: the
  // deflection states of tooth 1's filter, then Kt_p, Kr_p of every filter).
  Eigen::VectorXd final_state;
  Eigen::VectorXd covariance_diagonal;
  EstimateHistory history;
  std::int64_t steps = 0;    // filter steps (predict + update) per filter
  double runtime_s = 0.0;    // wall time of the step loop
  double time_step_s = 0.0;  // T
  int filters = 0;           // filters run (per-tooth: n)
  // Consistency of the innovations (analysis/kalman/consistency.h): mean NIS over the run with
  // the two-sided 95 % chi-square band of that mean and the fraction of updates inside the
  // per-update band chi-square(measured axes). A mean far below the band: R or Q larger than the
  // data's noise (the default tuning's R is a deflection sd of 10 um); far above: overconfident.
  // Per tooth: pooled over the n filters (they share z, so the pooled band, which assumes
  // independent updates, is too narrow; nis_per_filter has each filter's own).
  kalman::NisSummary nis;
  std::vector<kalman::NisSummary> nis_per_filter;  // one per filter

  // Final value of `key`; NaN if the variant does not estimate it.
  double value(const std::string& key) const;
};

// Throw InputError (naming cut.*, setup.*, inputs.*, ekf.*) for bad input; return a failed
// summary when the estimate leaves the finite numbers.
EkfResult ekf_modal(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                    const ModalEkfInputs& inputs, const ModalEkfOptions& options = {});
EkfResult ekf_coeff(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                    const CoeffEkfInputs& inputs, const CoeffEkfOptions& options = {});

inline EkfResult ekf_modal_x(const MeasuredCut& cut, const CutSetup& setup,
                             const ModalEkfInputs& inputs, const ModalEkfOptions& options = {}) {
  return ekf_modal(EstimatorId::kModalX, cut, setup, inputs, options);
}
inline EkfResult ekf_modal_xy(const MeasuredCut& cut, const CutSetup& setup,
                              const ModalEkfInputs& inputs, const ModalEkfOptions& options = {}) {
  return ekf_modal(EstimatorId::kModalXy, cut, setup, inputs, options);
}
inline EkfResult ekf_modal_xy_mk(const MeasuredCut& cut, const CutSetup& setup,
                                 const ModalEkfInputs& inputs,
                                 const ModalEkfOptions& options = {}) {
  return ekf_modal(EstimatorId::kModalXyMk, cut, setup, inputs, options);
}
inline EkfResult ekf_modal_xy_mc(const MeasuredCut& cut, const CutSetup& setup,
                                 const ModalEkfInputs& inputs,
                                 const ModalEkfOptions& options = {}) {
  return ekf_modal(EstimatorId::kModalXyMc, cut, setup, inputs, options);
}
inline EkfResult ekf_coeff_xy(const MeasuredCut& cut, const CutSetup& setup,
                              const CoeffEkfInputs& inputs, const CoeffEkfOptions& options = {}) {
  return ekf_coeff(EstimatorId::kCoeffXy, cut, setup, inputs, options);
}
inline EkfResult ekf_coeff_xy_per_tooth(const MeasuredCut& cut, const CutSetup& setup,
                                        const CoeffEkfInputs& inputs,
                                        const CoeffEkfOptions& options = {}) {
  return ekf_coeff(EstimatorId::kCoeffXyPerTooth, cut, setup, inputs, options);
}

}  // namespace estimate
}  // namespace chatterlab
