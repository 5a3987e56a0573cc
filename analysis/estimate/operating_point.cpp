#include "analysis/estimate/operating_point.h"

#include <algorithm>
#include <cstddef>
#include <string>

namespace chatterlab {
namespace estimate {

OperatingSample largest_force_sample(const MeasuredCut& cut, const CutSetup& setup,
                                     const std::vector<ToothCoefficients>& k) {
  const CutChips chips(cut, setup);
  OperatingSample best;
  double largest = -1.0;
  for (Eigen::Index i = std::max<Eigen::Index>(chips.first_step(), 1); i + 1 < chips.samples();
       ++i) {
    const StepChips c = chips.chips(i);
    const double f = cutting_force_N(c, k).norm();
    if (f > largest) {
      largest = f;
      best.k = i;
      best.chips = c;
    }
  }
  const Eigen::Index i = best.k;
  const double T = cut.time_step_s;
  best.deflection << cut.x_m[i], (cut.x_m[i + 1] - cut.x_m[i - 1]) / (2 * T), cut.y_m[i],
      (cut.y_m[i + 1] - cut.y_m[i - 1]) / (2 * T);
  return best;
}

namespace {

// Every variant's state is its measured axes' deflection states, then its estimate keys
// (one tooth's for per_tooth).
constexpr bool states_are_deflections_then_keys() {
  for (const EstimatorInfo& e : kEstimators) {
    if (e.states != 2 * e.measured_axes + e.key_count) return false;
  }
  return true;
}
static_assert(states_are_deflections_then_keys());

// The tooth with the largest chip b w (the first on a tie).
int largest_chip_tooth(const StepChips& c) {
  int p = 0;
  double bw = -1.0;
  for (int q = 0; q < c.teeth; ++q) {
    if (c.tooth[static_cast<std::size_t>(q)].bw_m2 > bw) {
      bw = c.tooth[static_cast<std::size_t>(q)].bw_m2;
      p = q;
    }
  }
  return p;
}

}  // namespace

OperatingState operating_state(const EkfResult& r, const OperatingSample& op,
                               const std::vector<ToothCoefficients>& k,
                               const ModalParameters& identified) {
  const EstimatorInfo& e = estimator_info(r.id);
  OperatingState s;
  s.held = identified;
  // The force input, by the row's kind (modal, per_tooth).
  ForceInput& u = s.input;
  int tooth = 0;  // per_tooth: the filter taken
  if (e.modal) {
    u.known_N = cutting_force_N(op.chips, k);
  } else if (!e.per_tooth) {
    for (int p = 0; p < op.chips.teeth; ++p) {
      u.regressor_m2 += tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(p)]);
    }
  } else {
    tooth = largest_chip_tooth(op.chips);
    u.regressor_m2 = tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(tooth)]);
    std::vector<ToothCoefficients> others = k;
    others[static_cast<std::size_t>(tooth)] = {0.0, 0.0};
    u.known_N = cutting_force_N(op.chips, others);
  }
  // The state: x, xdot (and y, ydot for two measured axes), then the final values of the row's
  // keys, the last key_count of estimate_keys (per_tooth: those of tooth + 1).
  const int deflections = 2 * e.measured_axes;
  const std::vector<std::string> keys = estimate_keys(r.id, tooth + 1);
  const std::size_t first_key = keys.size() - static_cast<std::size_t>(e.key_count);
  s.state.resize(e.states);
  s.state.head(deflections) = op.deflection.head(deflections);
  for (int j = 0; j < e.key_count; ++j) {
    s.state[deflections + j] = r.value(keys[first_key + static_cast<std::size_t>(j)]);
  }
  return s;
}

}  // namespace estimate
}  // namespace chatterlab
