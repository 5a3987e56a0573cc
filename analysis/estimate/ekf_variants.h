// The six EKF estimators of EXPERIMENT_FORMAT.md (000 ch. 4 and 6) run over a measured cut.
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
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/ekf_options.h"
#include "analysis/estimate/tool_model.h"

namespace chatterlab {
namespace estimate {

enum class EstimatorId {
  kModalX,
  kModalXy,
  kModalXyMk,
  kModalXyMc,
  kCoeffXy,
  kCoeffXyPerTooth,
};

// "ekf-modal-x", ... (EXPERIMENT_FORMAT.md).
const char* estimator_name(EstimatorId id);
// Inverse of estimator_name; throws InputError for an unknown name.
EstimatorId estimator_from_name(const std::string& name);
// Number of states of one filter of the variant (5, 7, 6, 6, 6, 6).
int estimator_states(EstimatorId id);
bool is_modal(EstimatorId id);

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
