// Discrete extended Kalman filter (000 eqs 4.5-4.9, after Simon [55] of 000) over a model type:
//
//   predict:  x-_k = f(x+_k-1, u_k-1)                       (noise-free, eq. 4.5)
//             P-_k = F P+_k-1 F^T + Q_d(x+_k-1),  F = J_f_x at (x+_k-1, u_k-1)   (eq. 4.6;
//             its upper triangle mirrored, so P stays symmetric when no measurement follows)
//   update:   S = H P-_k H^T + R,  H = J_h_x at x-_k,  K = P-_k H^T S^-1        (eq. 4.7)
//             x+_k = x-_k + K (z_k - h(x-_k))                                    (eq. 4.8)
//             P+_k = P-_k - K H P-_k, exactly symmetric (eq. 4.9), or the Joseph form
//
// Q_d = L Q L^T is the covariance the process noise adds over one step (L = J_f_w); the model
// adds it to P itself, so a model whose noise enters a few states can skip the zeros. The update
// is measurement_update.h (LDLT of S, consider states, NIS); the estimate, its accessors, the
// covariance prediction and the multirate update are KalmanFilterBase's (filter_base.h), shared
// with KalmanFilter.
//
// Model interface (every matrix fixed-size; nothing here may allocate):
//
//   struct Model {
//     static constexpr int kStates = N;          // size of x
//     static constexpr int kMeasurements = M;    // size of z
//     using State = kalman::Matrix<N, 1>;
//     using Measurement = kalman::Matrix<M, 1>;
//     using Input = ...;                         // any type: u of f(x, u)
//     // x' = f(x, u), and F = J_f_x (N x N) when J_f_x is not null.
//     State propagate(const State& x, const Input& u, Matrix<N, N>* J_f_x) const;
//     // P += Q_d(x) (N x N): the process noise covariance over one step from x.
//     void add_process_noise(const State& x, Matrix<N, N>* P) const;
//     // h(x), and H = J_h_x (M x N) when J_h_x is not null.
//     Measurement measure(const State& x, Matrix<M, N>* J_h_x) const;
//     // R (M x M), symmetric positive definite.
//     const Matrix<M, M>& measurement_noise() const;
//     // Optional: when h(x)_i = x_j with j = measured_state(i) (H selects states), the filter
//     // forms P- H^T and H P- H^T by selection instead of products (the same numbers, fewer
//     // operations).
//     static constexpr int measured_state(int i);
//   };
//
// An unscented filter fits the same interface: it calls propagate and measure on its sigma
// points with null Jacobians, takes Q_d from add_process_noise on a zero matrix and R from
// measurement_noise (additive-noise UKF), and can reuse MeasurementSubset for a multirate update.
// Its update has the cross covariance P_xz in place of P- H^T and P_zz + R in place of S; the
// standard form P+ = P- - K S K^T applies, the Joseph form (which needs H) does not.
#pragma once

#include <type_traits>

#include "analysis/kalman/filter_base.h"
#include "analysis/kalman/filter_types.h"
#include "analysis/kalman/measurement_update.h"

namespace chatterlab {
namespace kalman {

// True when Model declares static measured_state(i) (H selects states).
template <class Model, class = void>
struct SelectsStates : std::false_type {};
template <class Model>
struct SelectsStates<Model, std::void_t<decltype(Model::measured_state(0))>> : std::true_type {};

template <class Model>
class ExtendedKalmanFilter : public KalmanFilterBase<ExtendedKalmanFilter<Model>, Model,
                                                     Model::kStates, Model::kMeasurements> {
  using Base =
      KalmanFilterBase<ExtendedKalmanFilter<Model>, Model, Model::kStates, Model::kMeasurements>;
  friend Base;

 public:
  static constexpr int N = Model::kStates;
  static constexpr int M = Model::kMeasurements;
  using typename Base::Measurement;
  using typename Base::State;
  using typename Base::StateMatrix;
  using Input = typename Model::Input;
  using MeasurementJacobian = Matrix<M, N>;
  static_assert(std::is_same_v<typename Model::State, State> &&
                    std::is_same_v<typename Model::Measurement, Measurement>,
                "Model::State and Model::Measurement are kalman::Matrix<N, 1>, Matrix<M, 1>");

  // @param model the process and measurement model (see above).
  // @param x0 initial estimate x+_0 (N).
  // @param P0 its covariance (N x N), symmetric positive semi-definite.
  ExtendedKalmanFilter(const Model& model, const State& x0, const StateMatrix& P0,
                       const FilterOptions& options = {})
      : Base(model, x0, P0, options) {}

  // @param u input u_k-1 of f.
  void predict(const Input& u) {
    StateMatrix F;
    const State x_prior = this->model_.propagate(this->x_, u, &F);
    this->predict_covariance(F, [this](StateMatrix& P) {
      this->model_.add_process_noise(this->x_, &P);  // Q_d at x+_k-1
    });
    this->x_ = x_prior;
  }

  // update(z) and update(z, present, considered): KalmanFilterBase (filter_base.h).

  // Schmidt update: the states in `considered` keep their estimates (their gain rows are zero);
  // the covariance is the exact one of that gain (measurement_update.h).
  // @param z measurement (M); @param considered consider states.
  Innovation update_consider(const Measurement& z, const StateMask<N>& considered) {
    return update_all(z, &considered);
  }

 private:
  Innovation update_all(const Measurement& z, const StateMask<N>* considered) {
    const Model& model = this->model_;
    const Matrix<M, M>& R = model.measurement_noise();
    if constexpr (SelectsStates<Model>::value) {
      // P- H^T and S are selections of P-; the constant H (for the Joseph form) is H_.
      const Matrix<N, N>& P = this->P_;
      const Measurement nu = z - model.measure(this->x_, nullptr);
      Matrix<N, M> PHt;
      Matrix<M, M> S;
      for (int i = 0; i < M; ++i) PHt.col(i) = P.col(Model::measured_state(i));
      for (int i = 0; i < M; ++i) {
        for (int j = 0; j < M; ++j) S(i, j) = PHt(Model::measured_state(i), j) + R(i, j);
      }
      return gain_update<N, M, M>(nu, PHt, S, H_, R, considered, this->options_.covariance_update,
                                  this->x_, this->P_);
    } else {
      MeasurementJacobian H;
      const Measurement nu = z - model.measure(this->x_, &H);
      return this->update_with(nu, H, R, considered);
    }
  }

  MeasurementSubset<N, M> subset(const Measurement& z, const MeasurementMask<M>& present) const {
    MeasurementJacobian H;
    const Measurement h = this->model_.measure(this->x_, &H);
    return MeasurementSubset<N, M>(z, h, H, this->model_.measurement_noise(), present);
  }

  static MeasurementJacobian selection() {
    MeasurementJacobian H = MeasurementJacobian::Zero();
    if constexpr (SelectsStates<Model>::value) {
      for (int i = 0; i < M; ++i) H(i, Model::measured_state(i)) = 1.0;
    }
    return H;
  }

  MeasurementJacobian H_ = selection();  // H of a selecting model (zero otherwise, unused)
};

}  // namespace kalman
}  // namespace chatterlab
