// The EKFs of 000 ch. 4 on the core filter: ToolModel (tool_model.h) with its noise tuning in the
// model interface of kalman::ExtendedKalmanFilter, whose step is 000 eqs 4.5-4.9 (Simon [55]):
//
//   predict (eqs 4.5-4.6):  x^-_k = f(x^+_k-1, u_k-1, 0)
//                           P^-_k = F P^+_k-1 F^T + L Q L^T,  F = J_f_x, L = J_f_w at x^+_k-1
//     (eq. 4.6 as printed multiplies P^+_k; the prior is propagated from P^+_k-1.)
//   update (eqs 4.7-4.9):   S = H P^- H^T + R     (M = I: eqs 4.13, 4.20, 4.28), LDLT of S
//                           K = P^- H^T S^-1
//                           x^+ = x^- + K (z - H x^-)
//                           P^+ = P^- - K H P^-   (= (I - K H) P^-, exactly symmetric)
// H selects the measured deflections (ToolModel::measured_state); Q = diag(q), R = diag(r).
//
// Parameter hold: filter.update_consider(z, parameter_states<Tool>()) is the Schmidt "consider"
// update. The deflection and velocity states take their optimal gain, the parameter rows of K
// are zero, and the covariance is the exact covariance of that suboptimal gain (Joseph form):
// P^+ = P^- - A with A = P^- H^T S^-1 H P^- except that A's parameter-parameter block is zero.
#pragma once

#include <Eigen/Core>

#include "analysis/estimate/cut_input.h"
#include "analysis/estimate/tool_model.h"
#include "analysis/kalman/extended_kalman_filter.h"
#include "analysis/kalman/unscented_kalman_filter.h"

namespace chatterlab {
namespace estimate {

// A ToolModel with its Q and R in the model interface of kalman::ExtendedKalmanFilter.
template <class Tool>
class ToolEkfModel {
 public:
  static constexpr int kStates = Tool::kStates;
  static constexpr int kMeasurements = Tool::kMeasurements;
  using State = typename Tool::State;
  using Input = ForceInput;
  using Measurement = typename Tool::Measurement;
  using Noise = typename Tool::Noise;
  using StateMatrix = typename Tool::StateMatrix;
  using MeasurementJacobian = kalman::Matrix<kMeasurements, kStates>;
  using MeasurementMatrix = kalman::Matrix<kMeasurements, kMeasurements>;

  // @param tool process model; @param q diagonal of Q (Tool::kNoises: w_x, [w_y], one per
  // parameter); @param r diagonal of R (kMeasurements), m^2.
  ToolEkfModel(const Tool& tool, const Noise& q, const Measurement& r)
      : tool_(tool), q_(q), R_(r.asDiagonal()) {}

  State propagate(const State& x, const ForceInput& u, StateMatrix* J_f_x) const {
    return tool_.propagate(x, u, Noise::Zero(), J_f_x);
  }
  void add_process_noise(const State& x, StateMatrix* P) const {
    tool_.add_process_noise(x, q_, P);
  }
  // Measurement i is state measured_state(i) (the filter then selects instead of multiplying).
  static constexpr int measured_state(int i) { return Tool::measured_state(i); }
  // h(x): the measured deflections; J_h_x the selector H of 000 eqs 4.12, 4.19, 4.27.
  Measurement measure(const State& x, MeasurementJacobian* J_h_x) const {
    Measurement h;
    if (J_h_x) J_h_x->setZero();
    for (int i = 0; i < kMeasurements; ++i) {
      h[i] = x[Tool::measured_state(i)];
      if (J_h_x) (*J_h_x)(i, Tool::measured_state(i)) = 1.0;
    }
    return h;
  }
  const MeasurementMatrix& measurement_noise() const { return R_; }
  const Tool& tool() const { return tool_; }

 private:
  Tool tool_;
  Noise q_;
  MeasurementMatrix R_;
};

template <class Tool>
using ToolEkf = kalman::ExtendedKalmanFilter<ToolEkfModel<Tool>>;
// The unscented filter on the same model (kalman/unscented_kalman_filter.h).
template <class Tool>
using ToolUkf = kalman::UnscentedKalmanFilter<ToolEkfModel<Tool>>;

// The states the parameter hold keeps: m, c, k or Kt, Kr (the last Tool::kParameters).
template <class Tool>
kalman::StateMask<Tool::kStates> parameter_states() {
  kalman::StateMask<Tool::kStates> s;
  for (int i = Tool::kFirstParameter; i < Tool::kStates; ++i) s.set(static_cast<std::size_t>(i));
  return s;
}

// @param tool process model; @param x0 initial estimate (Tool::kStates); @param P0 its covariance
// (kStates x kStates); @param q diagonal of Q (Tool::kNoises); @param r diagonal of R
// (Tool::kMeasurements).
template <class Tool>
ToolEkf<Tool> make_tool_ekf(const Tool& tool, const typename Tool::State& x0,
                            const typename Tool::StateMatrix& P0, const typename Tool::Noise& q,
                            const typename Tool::Measurement& r) {
  return ToolEkf<Tool>(ToolEkfModel<Tool>(tool, q, r), x0, P0);
}

// The unscented filter of the same model, noise and initial estimate as make_tool_ekf.
template <class Tool>
ToolUkf<Tool> make_tool_ukf(const Tool& tool, const typename Tool::State& x0,
                            const typename Tool::StateMatrix& P0, const typename Tool::Noise& q,
                            const typename Tool::Measurement& r,
                            const kalman::UnscentedOptions& options) {
  return ToolUkf<Tool>(ToolEkfModel<Tool>(tool, q, r), x0, P0, options);
}

}  // namespace estimate
}  // namespace chatterlab
