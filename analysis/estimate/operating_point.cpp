#include "analysis/estimate/operating_point.h"

#include <algorithm>
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

OperatingState operating_state(const EkfResult& r, const OperatingSample& op,
                               const std::vector<ToothCoefficients>& k,
                               const ModalParameters& identified) {
  OperatingState s;
  s.held = identified;
  ForceInput& u = s.input;
  Eigen::VectorXd& state = s.state;
  const auto value = [&r](const char* key) { return r.value(key); };
  switch (r.id) {
    case EstimatorId::kModalX:
      u.known_N = cutting_force_N(op.chips, k);
      state.resize(5);
      state << op.deflection[0], op.deflection[1], value("m_kg"), value("c_kg_s"), value("k_N_m");
      break;
    case EstimatorId::kModalXy:
      u.known_N = cutting_force_N(op.chips, k);
      state.resize(7);
      state << op.deflection, value("m_kg"), value("c_kg_s"), value("k_N_m");
      break;
    case EstimatorId::kModalXyMk:
      u.known_N = cutting_force_N(op.chips, k);
      state.resize(6);
      state << op.deflection, value("m_kg"), value("k_N_m");
      break;
    case EstimatorId::kModalXyMc:
      u.known_N = cutting_force_N(op.chips, k);
      state.resize(6);
      state << op.deflection, value("m_kg"), value("c_kg_s");
      break;
    case EstimatorId::kCoeffXy:
      for (int p = 0; p < op.chips.teeth; ++p) {
        u.regressor_m2 += tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(p)]);
      }
      state.resize(6);
      state << op.deflection, value("Kt_N_m2"), value("Kr_N_m2");
      break;
    case EstimatorId::kCoeffXyPerTooth: {
      int p = 0;
      double bw = -1.0;
      for (int q = 0; q < op.chips.teeth; ++q) {
        if (op.chips.tooth[static_cast<std::size_t>(q)].bw_m2 > bw) {
          bw = op.chips.tooth[static_cast<std::size_t>(q)].bw_m2;
          p = q;
        }
      }
      u.regressor_m2 = tooth_regressor_m2(op.chips.tooth[static_cast<std::size_t>(p)]);
      std::vector<ToothCoefficients> others = k;
      others[static_cast<std::size_t>(p)] = {0.0, 0.0};
      u.known_N = cutting_force_N(op.chips, others);
      state.resize(6);
      const std::string n = std::to_string(p + 1);
      state << op.deflection, r.value("Kt" + n + "_N_m2"), r.value("Kr" + n + "_N_m2");
      break;
    }
  }
  return s;
}

}  // namespace estimate
}  // namespace chatterlab
