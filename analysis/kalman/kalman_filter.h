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
class KalmanFilter {
 public:
  static constexpr int kStates = N;
  static constexpr int kInputs = U;
  static constexpr int kMeasurements = M;
  using Model = LinearModel<N, U, M>;
  using State = Matrix<N, 1>;
  using StateMatrix = Matrix<N, N>;
  using Input = Matrix<U, 1>;
  using Measurement = Matrix<M, 1>;

  // @param model A (N x N), B (N x U), C (M x N), Q (N x N), R (M x M).
  // @param x0 estimate of x[0] (N).
  // @param P0 its covariance (N x N), symmetric positive semi-definite.
  KalmanFilter(const Model& model, const State& x0, const StateMatrix& P0,
               const FilterOptions& options = {})
      : model_(model), x_(x0), P_(P0), options_(options) {}

  // @param u input u[k] (U).
  void predict(const Input& u) {
    x_ = model_.A * x_ + model_.B * u;
    const StateMatrix AP = model_.A * P_;
    P_.noalias() = AP * model_.A.transpose();
    P_ += model_.Q;
    P_.template triangularView<Eigen::StrictlyLower>() = P_.transpose();
  }

  // @param z measurement of the current state (M).
  Innovation update(const Measurement& z) { return update(z, all_rows<M>(), StateMask<N>()); }

  // Only the rows of z marked in `present` (the others are ignored, whatever their value). An
  // empty mask leaves the estimate as it is and returns dimension 0.
  // @param z measurement (M); @param present rows of z that arrived.
  // @param considered consider states: not corrected (see measurement_update.h).
  Innovation update(const Measurement& z, const MeasurementMask<M>& present,
                    const StateMask<N>& considered = StateMask<N>()) {
    if (present.all()) {
      const Measurement nu = z - model_.C * x_;
      return measurement_update<N, M, M>(nu, model_.C, model_.R, &considered,
                                         options_.covariance_update, x_, P_);
    }
    if (present.none()) return Innovation{std::numeric_limits<double>::quiet_NaN(), 0};
    const MeasurementSubset<N, M> s(z, model_.C * x_, model_.C, model_.R, present);
    return measurement_update<N, Eigen::Dynamic, M>(s.nu, s.H, s.R, &considered,
                                                    options_.covariance_update, x_, P_);
  }

  const State& state() const { return x_; }
  const StateMatrix& covariance() const { return P_; }
  const Model& model() const { return model_; }
  void set_state(const State& x, const StateMatrix& P) {
    x_ = x;
    P_ = P;
  }

 private:
  Model model_;
  State x_;
  StateMatrix P_;
  FilterOptions options_;
};

}  // namespace kalman
}  // namespace chatterlab
