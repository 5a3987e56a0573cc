// Discrete linear Kalman filter (000 eqs 4.5-4.9 with f and h linear) for the model
//
//   x[k+1] = A x[k] + B u[k] + w[k],   w ~ N(0, Q)
//   z[k]   = C x[k] + v[k],            v ~ N(0, R)
//
//   predict:  x- = A x+ + B u,   P- = A P+ A^T + Q (upper triangle mirrored: exactly symmetric)
//   update:   S = C P- C^T + R,  K = P- C^T S^-1,  x+ = x- + K (z - C x-),
//             P+ = P- - K C P- (or the Joseph form; measurement_update.h)
//
// The filter holds the estimate of the current state and its covariance: construct it with the
// prior of x[0], then predict() moves it one step and update() takes a measurement of the state
// it holds. Fixed-size matrices throughout: a step allocates nothing. For the steady-state gain
// of this model see dare.h.
#pragma once

#include "analysis/kalman/filter_base.h"
#include "analysis/kalman/filter_types.h"
#include "analysis/kalman/measurement_update.h"

namespace chatterlab {
namespace kalman {

// N states, U inputs (0 allowed), M measurements.
template <int N, int U, int M>
struct LinearModel {
  Matrix<N, N> A = Matrix<N, N>::Identity();  // state transition (N x N)
  Matrix<N, U> B = Matrix<N, U>::Zero();      // input matrix (N x U)
  Matrix<M, N> C = Matrix<M, N>::Zero();      // measurement matrix (M x N)
  Matrix<N, N> Q = Matrix<N, N>::Zero();      // process noise covariance (N x N), PSD
  Matrix<M, M> R = Matrix<M, M>::Identity();  // measurement noise covariance (M x M), PD
};

template <int N, int U, int M>
class KalmanFilter : public KalmanFilterBase<KalmanFilter<N, U, M>, LinearModel<N, U, M>, N, M> {
  using Base = KalmanFilterBase<KalmanFilter<N, U, M>, LinearModel<N, U, M>, N, M>;
  friend Base;

 public:
  static constexpr int kStates = N;
  static constexpr int kInputs = U;
  static constexpr int kMeasurements = M;
  using Model = LinearModel<N, U, M>;
  using typename Base::Measurement;
  using typename Base::State;
  using typename Base::StateMatrix;
  using Input = Matrix<U, 1>;

  // @param model A (N x N), B (N x U), C (M x N), Q (N x N), R (M x M).
  // @param x0 estimate of x[0] (N).
  // @param P0 its covariance (N x N), symmetric positive semi-definite.
  KalmanFilter(const Model& model, const State& x0, const StateMatrix& P0,
               const FilterOptions& options = {})
      : Base(model, x0, P0, options) {}

  // @param u input u[k] (U).
  void predict(const Input& u) {
    const Model& m = this->model_;
    this->x_ = m.A * this->x_ + m.B * u;
    this->predict_covariance(m.A, [&m](StateMatrix& P) { P += m.Q; });
  }

  // update(z) and update(z, present, considered): KalmanFilterBase (filter_base.h).

 private:
  // nu = z - C x-, H = C.
  Innovation update_all(const Measurement& z, const StateMask<N>* considered) {
    const Model& m = this->model_;
    return this->update_with(z - m.C * this->x_, m.C, m.R, considered);
  }
  MeasurementSubset<N, M> subset(const Measurement& z, const MeasurementMask<M>& present) const {
    const Model& m = this->model_;
    return MeasurementSubset<N, M>(z, m.C * this->x_, m.C, m.R, present);
  }
};

}  // namespace kalman
}  // namespace chatterlab
