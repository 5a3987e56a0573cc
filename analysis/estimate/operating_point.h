// The operating point of 000 sec. 4.5 at which each estimator variant's observability rank is
// taken (observability.h, 000 eq. 4.33): the sample of the window with the largest cutting
// force (a tooth cuts), the deflections measured there with velocities by central difference,
// and the variant's parameters at its run's final estimates.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/ekf_variants.h"
#include "analysis/estimate/tool_model.h"

namespace chatterlab {
namespace estimate {

struct OperatingSample {
  Eigen::Index k = 0;  // sample index in the cut
  StepChips chips;     // every tooth's chip there
  // x, dx/dt, y, dy/dt: measured deflections, velocities (x[k+1] - x[k-1]) / (2 T).
  Eigen::Vector4d deflection = Eigen::Vector4d::Zero();
};

// The sample k in [max(first_step, 1), samples - 2] where |cutting_force_N(chips(k),
// coefficients)| is largest (the first such sample on a tie).
// @param coefficients  one per tooth (cutting_force_N)
// @throws InputError as CutChips for a bad cut or setup
OperatingSample largest_force_sample(const MeasuredCut& cut, const CutSetup& setup,
                                     const std::vector<ToothCoefficients>& coefficients);

// One variant's state, force input and held m, c, k at the operating sample (the arguments of
// observability()), laid out by the variant's row of kEstimators (measured_axes, keys, modal,
// per_tooth):
//  - modal variants: the deflection states (x, xdot for ekf-modal-x; all four otherwise), then
//    the run's final m, c, k among those it estimates; the whole cutting force with the
//    identified coefficients known; held m, c, k the identified ones;
//  - ekf-coeff-xy: the four deflection states and its final Kt, Kr; the regressor summed over
//    the teeth;
//  - ekf-coeff-xy-per-tooth: the filter of the tooth with the largest chip there (each filter
//    has the same structure), its final Kt_p, Kr_p; the other teeth's force known with the
//    identified coefficients.
// @param run  a successful run of the variant (its id and final estimates)
struct OperatingState {
  Eigen::VectorXd state;
  ForceInput input;
  ModalParameters held;
};
OperatingState operating_state(const EkfResult& run, const OperatingSample& at,
                               const std::vector<ToothCoefficients>& identified_coefficients,
                               const ModalParameters& identified_modal);

}  // namespace estimate
}  // namespace chatterlab
