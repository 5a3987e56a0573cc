// Repeatability of an EKF over randomized initial estimates (000 sec. 6.2, figs 6.19-6.20: ten
// consecutive trials with initial coefficients drawn within +-50 % of the identified values).
//
// Run r starts every estimated parameter at reference * (1 + spread * (2 u - 1)), u uniform in
// [0, 1) from a std::mt19937_64 seeded with `seed` (u = top 53 bits / 2^53, so the draws are the
// same on every platform); held parameters and the known inputs stay at their reference values.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/estimate/ekf_variants.h"

namespace chatterlab {
namespace estimate {

struct RepeatabilityOptions {
  int runs = 10;           // trials, >= 2 (000 sec. 6.2: ten)
  double spread = 0.5;     // half-width of the uniform draw, relative, in [0, 1) (000: +-50 %)
  std::uint64_t seed = 1;  // seed of the local generator
};

struct RepeatabilityResult {
  StepSummary summary;            // failed if any run failed (its message names the run)
  std::vector<std::string> keys;  // the variant's estimate keys
  Eigen::MatrixXd initial;        // runs x keys: the drawn initial estimates
  Eigen::MatrixXd finals;         // runs x keys: final estimates (NaN for a failed run)
  // Over the successful runs, per key:
  Eigen::VectorXd mean, std_dev, min, max, range;  // std_dev: sample (n - 1) standard deviation
  std::vector<EkfResult> runs;                     // every run, with its history (figs 6.19-6.20)
};

// Reference: inputs.start (modal) or inputs.start (coefficients), i.e. the values the draws
// scatter around. Throws InputError for bad options (repeat.*) or inputs (as the filters do).
RepeatabilityResult repeat_modal(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                                 const ModalEkfInputs& reference,
                                 const ModalEkfOptions& options = {},
                                 const RepeatabilityOptions& repeat = {});
RepeatabilityResult repeat_coeff(EstimatorId id, const MeasuredCut& cut, const CutSetup& setup,
                                 const CoeffEkfInputs& reference,
                                 const CoeffEkfOptions& options = {},
                                 const RepeatabilityOptions& repeat = {});

}  // namespace estimate
}  // namespace chatterlab
