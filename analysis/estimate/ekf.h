// Discrete extended Kalman filter of 000 eqs 4.5-4.9 (Simon [55]) over a ToolModel, with
// fixed-size matrices throughout: a step allocates nothing.
//
//   predict (eqs 4.5-4.6):  x^-_k = f(x^+_k-1, u_k-1, 0)
//                           P^-_k = F P^+_k-1 F^T + L Q L^T,  F = J_f_x, L = J_f_w at x^+_k-1
//     (eq. 4.6 as printed multiplies P^+_k; the prior is propagated from P^+_k-1.)
//   update (eqs 4.7-4.9):   S = H P^- H^T + R     (M = I: eqs 4.13, 4.20, 4.28)
//                           K = P^- H^T S^-1
//                           x^+ = x^- + K (z - H x^-)
//                           P^+ = P^- - K H P^-   (= (I - K H) P^-, symmetrised)
// H selects the measured deflections (ToolModel::measured_state).
//
// Parameter hold (update_parameters = false): the Schmidt "consider" update. The deflection and
// velocity states take their optimal gain, the parameter rows of K are zero, and the covariance
// is the exact covariance of that suboptimal gain (Joseph form): P^+ = P^- - A with
// A = P^- H^T S^-1 H P^- except that A's parameter-parameter block is zero.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include "analysis/estimate/cut_input.h"

namespace chatterlab {
namespace estimate {

template <class Model>
class ExtendedKalmanFilter {
 public:
  static constexpr int N = Model::kStates;
  static constexpr int W = Model::kNoises;
  static constexpr int Z = Model::kMeasurements;
  static constexpr int kParameters = Model::kParameters;
  using State = typename Model::State;
  using StateMatrix = typename Model::StateMatrix;
  using Noise = typename Model::Noise;
  using Measurement = typename Model::Measurement;

  // @param x0 initial estimate (N);  @param P0 initial covariance (N x N);
  // @param q diagonal of Q (W: w_x, [w_y], one per parameter);  @param r diagonal of R (Z).
  ExtendedKalmanFilter(const Model& model, const State& x0, const StateMatrix& P0, const Noise& q,
                       const Measurement& r)
      : model_(model), x_(x0), P_(P0), q_(q), r_(r) {}

  void predict(const ForceInput& u) {
    StateMatrix F;
    const State x_prior = model_.propagate(x_, u, Noise::Zero(), &F);
    const StateMatrix FP = F * P_;
    P_.noalias() = FP * F.transpose();
    model_.add_process_noise(x_, q_, &P_);
    x_ = x_prior;
  }

  void update(const Measurement& z, bool update_parameters = true) {
    Eigen::Matrix<double, N, Z> PHt;
    Measurement innovation;
    for (int i = 0; i < Z; ++i) {
      PHt.col(i) = P_.col(Model::measured_state(i));
      innovation[i] = z[i] - x_[Model::measured_state(i)];
    }
    Eigen::Matrix<double, Z, Z> S;
    for (int i = 0; i < Z; ++i) {
      for (int j = 0; j < Z; ++j) S(i, j) = PHt(Model::measured_state(i), j);
      S(i, i) += r_[i];
    }
    Eigen::Matrix<double, N, Z> K = PHt * S.inverse();
    StateMatrix A = K * PHt.transpose();
    if (!update_parameters && kParameters > 0) {
      K.template bottomRows<kParameters>().setZero();
      A.template bottomRightCorner<kParameters, kParameters>().setZero();
    }
    x_.noalias() += K * innovation;
    P_ -= A;
    P_ = 0.5 * (P_ + P_.transpose()).eval();
  }

  const State& state() const { return x_; }
  const StateMatrix& covariance() const { return P_; }
  const Model& model() const { return model_; }

 private:
  Model model_;
  State x_;
  StateMatrix P_;
  Noise q_;
  Measurement r_;
};

}  // namespace estimate
}  // namespace chatterlab
