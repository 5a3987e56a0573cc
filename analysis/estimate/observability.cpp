#include "analysis/estimate/observability.h"

#include <Eigen/SVD>
#include <cmath>
#include <sstream>
#include <string>

#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace estimate {

namespace {

template <class Model>
ObservabilityResult rank_of(const Eigen::VectorXd& state_in, const ForceInput& input,
                            const ModalParameters& held, double T,
                            const ObservabilityOptions& options) {
  constexpr int N = Model::kStates;
  constexpr int Z = Model::kMeasurements;
  // Forward Euler: F = I + T A with A the Jacobian of the continuous model (000 eq. 4.10).
  const Model model(T, Discretization::kForwardEuler, held);
  const typename Model::State x = state_in;
  const double m = model.mass(x), k = model.stiffness(x);
  require_rule(std::isfinite(m) && m > 0.0, "observability: m", m, "must be > 0");
  require_rule(std::isfinite(k) && k > 0.0, "observability: k", k, "must be > 0");
  const double wn = std::sqrt(k / m);

  typename Model::StateMatrix F;
  model.propagate(x, input, Model::Noise::Zero(), &F);
  const typename Model::StateMatrix A = (F - Model::StateMatrix::Identity()) / T;

  double d = 0.0;
  for (int a = 0; a < Model::kAxes; ++a) {
    d = std::max({d, std::abs(x[2 * a]), std::abs(x[2 * a + 1]) / wn});
  }
  if (d == 0.0) d = 1e-6;
  Eigen::Matrix<double, N, 1> s;
  for (int a = 0; a < Model::kAxes; ++a) {
    s[2 * a] = d;
    s[2 * a + 1] = wn * d;
  }
  for (int i = Model::kFirstParameter; i < N; ++i) s[i] = x[i] != 0.0 ? std::abs(x[i]) : 1.0;
  // Continuous: A~ = S^-1 A S / w_n. Eq. 4.33: F~ = S^-1 F S.
  const bool continuous = options.form == ObservabilityForm::kContinuous;
  const typename Model::StateMatrix M =
      continuous
          ? typename Model::StateMatrix(s.cwiseInverse().asDiagonal() * A * s.asDiagonal() / wn)
          : typename Model::StateMatrix(s.cwiseInverse().asDiagonal() * F * s.asDiagonal());
  Eigen::Matrix<double, Z, N> H = Eigen::Matrix<double, Z, N>::Zero();
  for (int i = 0; i < Z; ++i) H(i, Model::measured_state(i)) = s[Model::measured_state(i)] / d;

  Eigen::Matrix<double, Z * N, N> O;
  Eigen::Matrix<double, Z, N> block = H;
  for (int i = 0; i < N; ++i) {
    O.template middleRows<Z>(Z * i) = block;
    block = block * M;
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, Z * N, N>> svd(O);
  ObservabilityResult r;
  r.states = N;
  r.relative_tolerance = options.relative_tolerance;
  const Eigen::VectorXd sv = svd.singularValues();
  r.singular_values = sv / sv[0];
  for (Eigen::Index i = 0; i < sv.size(); ++i) {
    if (r.singular_values[i] > options.relative_tolerance) ++r.rank;
  }
  return r;
}

}  // namespace

ObservabilityResult observability(EstimatorId id, const Eigen::VectorXd& state,
                                  const ForceInput& input, const ModalParameters& held,
                                  double time_step_s, const ObservabilityOptions& options) {
  require_rule(state.size() == estimator_states(id), "observability: state.size()", state.size(),
               std::string("must be ") + std::to_string(estimator_states(id)) + " for " +
                   estimator_name(id));
  require_rule(state.allFinite(), "observability: state", "non-finite", "must be finite");
  require_rule(std::isfinite(time_step_s) && time_step_s > 0.0, "observability: time_step_s",
               time_step_s, "must be > 0");
  require_rule(options.form == ObservabilityForm::kContinuous ||
                   options.form == ObservabilityForm::kDiscreteEq4_33,
               "observability: form", static_cast<int>(options.form), "unknown form");
  require_rule(options.relative_tolerance > 0.0 && options.relative_tolerance < 1.0,
               "observability: relative_tolerance", options.relative_tolerance,
               "must be in (0, 1)");
  switch (structure_of(id)) {  // the UKFs share their EKF twin's model
    case EstimatorId::kModalX:
      return rank_of<ModalXModel>(state, input, held, time_step_s, options);
    case EstimatorId::kModalXy:
      return rank_of<ModalXyModel>(state, input, held, time_step_s, options);
    case EstimatorId::kModalXyMk:
      return rank_of<ModalXyMkModel>(state, input, held, time_step_s, options);
    case EstimatorId::kModalXyMc:
      return rank_of<ModalXyMcModel>(state, input, held, time_step_s, options);
    default:
      return rank_of<CoeffXyModel>(state, input, held, time_step_s, options);
  }
}

}  // namespace estimate
}  // namespace chatterlab
