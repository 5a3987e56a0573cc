// The project's small dense least-squares fits (tap-test modal fit, the dynamometer's transfer
// fit, the spindle sensor model, the joint identification of a cut) all solve with Ceres the
// same way: Levenberg-Marquardt, dense QR, silent, one thread (the fits run inside threads of
// their own). Each gives its iteration cap and tolerances. For .cpp files of the analysis
// library only (Ceres is its private dependency).
#pragma once

#include <ceres/ceres.h>

namespace chatterlab {

inline ceres::Solver::Options dense_lm_options(int max_iterations, double function_tolerance,
                                               double parameter_tolerance,
                                               double gradient_tolerance) {
  ceres::Solver::Options o;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = max_iterations;
  o.function_tolerance = function_tolerance;
  o.parameter_tolerance = parameter_tolerance;
  o.gradient_tolerance = gradient_tolerance;
  o.logging_type = ceres::SILENT;
  o.num_threads = 1;
  return o;
}

// Iterations a solve took (its steps, accepted or not; Ceres's iteration 0 is no step).
inline int lm_iterations(const ceres::Solver::Summary& s) {
  return s.num_successful_steps + s.num_unsuccessful_steps;
}

}  // namespace chatterlab
