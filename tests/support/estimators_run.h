// Every EKF variant (ekf_variants.h) run the one way the estimator tests that loop over
// all_estimators() run it: on a short synthetic cut (0.01 s after 5 settling revolutions) with
// 000 sec. 6.1's start values (modal variants: table 5.2's coefficients known; coefficient
// variants: table 5.2's m, c, k known, ekf-coeff-xy and ukf-coeff-xy from Kt, Kr = 2e9, 1e9).
#pragma once

#include <vector>

#include "analysis/estimate/ekf_variants.h"
#include "tests/support/synthetic_cuts.h"

namespace chatterlab::testing {

// The 0.01 s cut, simulated once.
inline const estimate::MeasuredCut& estimators_short_cut() {
  static const estimate::MeasuredCut cut = [] {
    SyntheticCutSpec spec;
    spec.record_s = 0.01;
    spec.settle_revolutions = 5;
    return synthetic_cut(spec);
  }();
  return cut;
}

// Runs variant `id` over `cut` with the start values above.
inline estimate::EkfResult run_estimator(estimate::EstimatorId id, const estimate::MeasuredCut& cut,
                                         const estimate::CutSetup& setup) {
  using estimate::EstimatorId;
  if (estimate::is_modal(id)) {
    return estimate::ekf_modal(id, cut, setup,
                               {table52_coefficients(), dissertation_start_modal()});
  }
  return estimate::ekf_coeff(
      id, cut, setup,
      {table52_modal(), estimate::structure_of(id) == EstimatorId::kCoeffXy
                            ? std::vector<estimate::ToothCoefficients>{{2e9, 1e9}}
                            : dissertation_start_coefficients()});
}

}  // namespace chatterlab::testing
