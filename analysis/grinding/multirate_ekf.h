// The multirate EKF of 002 (section IV, appendix B) over a series of grinding cycles, with the
// gaps of appendix B filled as the campaign format's section 7 rules them (docs/grinding.md):
//
//   start      X-(1,0) = (0, 0, d_s0[, R0]), P-(1,0) = diag(P0)
//   j = 0      an update with the fast channels (P, D_w) only
//   j >= 1     propagate from (i, j-1) by eqs 8 and 14 with the u of row j-1, then
//              j < n_i: update by eqs 15-16 with P, D_w;
//              j = n_i: one joint update by eqs 17-18 with P, D_w and every inspection value of
//              the cycle the estimator uses that is usable (none: fast channels only)
//   new cycle  no propagation: x2 = 0 with its row and column of P zeroed and its variance
//              P0.v; x1, x3, R0 carried over (eqs 12-13); R0's variance + R0_cycle_var. A
//              dressing before the cycle: x1 = 0 with its row and column reset to P0.Vw alone,
//              x3 - depth, x3's variance + dress_sd^2
//   late       the estimate at the end of cycle a is that of a filter that applied each
//              inspection usable by the end of cycle a at its own cycle end: the a priori
//              (X-, P-) at every (i, n_i) is stored, and an inspection that becomes usable at
//              the end of cycle a is applied at its stored point and the fast rows replayed
//              up to (a, n_a) before the update there
//
// The filter is kalman::ExtendedKalmanFilter (analysis/kalman) with 3 or 4 states and the
// measurement vector (P, D_w, d_s, R_a); a multirate update holds the rows present.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/grinding/grinding_model.h"

namespace chatterlab {
namespace grinding {

// The four estimators of the format's section 7 (002 table I).
enum class GrindingEstimatorId {
  kXInprocess,   // x1..x3; P, D_w; no inspection (case 1, setting 1)
  kX,            // x1..x3; P, D_w; d_s at the cycle end (case 1, setting 2, D_w kept)
  kXrInprocess,  // x1..x3, R0; P, D_w; d_s (case 2, setting 1)
  kXr,           // x1..x3, R0; P, D_w; d_s, R_a (case 2, setting 2, D_w kept)
};

struct GrindingEstimatorInfo {
  GrindingEstimatorId id;
  const char* name;  // results.json id
  bool estimates_R0;
  bool uses_ds;  // inspection d_s joins the end-of-cycle update
  bool uses_Ra;  // inspection R_a joins the end-of-cycle update
};

inline constexpr std::array<GrindingEstimatorInfo, 4> kGrindingEstimators = {{
    {GrindingEstimatorId::kXInprocess, "multirate-ekf-x-inprocess", false, false, false},
    {GrindingEstimatorId::kX, "multirate-ekf-x", false, true, false},
    {GrindingEstimatorId::kXrInprocess, "multirate-ekf-xr-inprocess", true, true, false},
    {GrindingEstimatorId::kXr, "multirate-ekf-xr", true, true, true},
}};

const GrindingEstimatorInfo& estimator_info(GrindingEstimatorId id);

// The fast record after calibration: one row per fast instant, cycles 1..N contiguous and in
// order; cycle i holds n_i + 1 rows (j = 0..n_i). u of the last row of a cycle is not used.
struct FastRecord {
  std::vector<int> cycle;
  Eigen::VectorXd u_mm_s;
  Eigen::VectorXd power_W;
  Eigen::VectorXd Dw_mm;
};

// One end-of-cycle inspection of the part finished at (cycle, n_cycle); NaN: not measured.
struct Inspection {
  int cycle = 0;
  int available_cycle = 0;  // >= cycle: the cycle at whose end it can first be used
  double ds_mm = std::numeric_limits<double>::quiet_NaN();
  double Ra_um = std::numeric_limits<double>::quiet_NaN();
  double roundness_um = std::numeric_limits<double>::quiet_NaN();
};

struct Dressing {
  int before_cycle = 0;  // dressed between cycle before_cycle - 1 and before_cycle
  double depth_mm = 0.0;
};

// test.yaml `noise:` and `filter:` (the variances of the state order Vw, v, ds, R0).
struct GrindingFilterSettings {
  double sample_period_s = 0.02;  // T_f = 1 / sample_rate_hz
  double power_sd_W = 100;
  double Dw_sd_mm = 0.01;
  double ds_sd_mm = 0.001;
  double Ra_sd_um = 0.01;
  std::array<double, 4> P0{10, 1e-7, 1e-6, 0.01};      // Vw_mm2, v_mm_s, ds_mm, R0_um
  std::array<double, 4> Q{0.04, 4e-11, 4e-9, 1.6e-7};  // added once per fast step
  double R0_cycle_var_um2 = 0.0;
  double dress_sd_mm = 0.0;
  bool joseph = true;  // Joseph-form covariance update (the results do not depend on it)
};

// The estimate at one instant: states (Vw, v, ds[, R0]) and 3 sqrt of P's diagonal.
struct GrindingEstimate {
  int cycle = 0, j = 0;
  Eigen::Vector4d x = Eigen::Vector4d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector4d three_sigma = Eigen::Vector4d::Constant(std::numeric_limits<double>::quiet_NaN());
};

// Per cycle, at (i, n_i): the a posteriori estimate after eqs 17-18, the a priori d_s just
// before that update (after any replay) and R_a of eq. 11 at X-(i, n_i) (xr ids).
struct CycleEstimate {
  GrindingEstimate posterior;
  double ds_prior_mm = std::numeric_limits<double>::quiet_NaN();
  double ds_prior_3sigma_mm = std::numeric_limits<double>::quiet_NaN();
  double Ra_pred_um = std::numeric_limits<double>::quiet_NaN();
  bool inspected = false;  // an inspection value joined an update at this cycle's end
  // Innovation diagnostics: the mean NIS per degree of freedom of the cycle's updates without
  // inspection values (as they happened), and the NIS per degree of freedom of the update
  // holding this cycle's inspection values (when it ran, also for a late one; NaN: none).
  double nis_fast_per_dof = std::numeric_limits<double>::quiet_NaN();
  double nis_inspection_per_dof = std::numeric_limits<double>::quiet_NaN();
  int nis_fast_dof = 0, nis_inspection_dof = 0;
  // The a posteriori covariance at (i, n_i) (the leading states x states block is used).
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
};

struct GrindingRun {
  GrindingEstimatorId id = GrindingEstimatorId::kXr;
  StepSummary summary;
  int states = 0;                            // 3 or 4
  std::vector<CycleEstimate> per_cycle;      // cycle order
  std::vector<GrindingEstimate> trajectory;  // every fast instant, as computed then
  // NIS sums and degrees of freedom: fast-only updates (once, as they happened) and updates
  // holding inspection values (a late one at its replay).
  double nis_fast_sum = 0.0;
  int nis_fast_dof = 0;
  double nis_end_sum = 0.0;
  int nis_end_dof = 0;
  long steps = 0;           // sum of n_i + 1
  long replayed_steps = 0;  // fast rows run again for late inspections
  double nis_fast_per_dof() const;
  double nis_end_per_dof() const;  // NaN when no update held an inspection value
};

// Checks the record (cycles 1..N contiguous, at least two rows each), the inspections (cycle in
// 1..N, available_cycle >= cycle, one row per cycle) and the dressings (before_cycle in 2..N);
// throws InputError naming what is wrong.
void check_series(const FastRecord& record, const std::vector<Inspection>& inspections,
                  const std::vector<Dressing>& dressings);

// Runs one estimator over the series (check_series first). Deterministic; allocates only its
// outputs.
GrindingRun run_grinding_estimator(GrindingEstimatorId id, const GrindingParameters& p,
                                   const GrindingFilterSettings& s, const FastRecord& record,
                                   const std::vector<Inspection>& inspections,
                                   const std::vector<Dressing>& dressings);

// NEES per degree of freedom (format section 7): the mean over cycles of e' P^-1 e / dim X, with
// e the a posteriori estimate at (i, n_i) minus `truth` (one row per cycle in order; columns
// Vw_mm2, v_mm_s, ds_mm, R0_um, the last unused by 3-state runs). NaN for a failed run.
double nees_per_dof(const GrindingRun& run, const Eigen::MatrixX4d& truth);

}  // namespace grinding
}  // namespace chatterlab
