// What KalmanFilter and ExtendedKalmanFilter share: the estimate they hold (x, P, the model and
// the options), its accessors, the covariance prediction of 000 eq. 4.6 and the measurement update
// of 000 eqs 4.7-4.9 over every row or over the rows that arrived (measurement_update.h).
//
// CRTP base: Derived (the filter) supplies
//
//   // The update with every row of z (considered: nullptr or the consider states).
//   Innovation update_all(const Measurement& z, const StateMask<N>* considered);
//   // The rows of z marked in `present` with h(x-), H and R (MeasurementSubset).
//   MeasurementSubset<N, M> subset(const Measurement& z, const MeasurementMask<M>& present) const;
//
// and reaches these hooks through the friend declaration of its base. Everything is fixed-size
// and inlined: the filters step as fast as when each wrote it out.
#pragma once

#include <limits>

#include "analysis/kalman/filter_types.h"
#include "analysis/kalman/measurement_update.h"

namespace chatterlab {
namespace kalman {

template <class Derived, class Model, int N, int M>
class KalmanFilterBase {
 public:
  using State = Matrix<N, 1>;
  using StateMatrix = Matrix<N, N>;
  using Measurement = Matrix<M, 1>;

  // @param z measurement of the current state (M), every row present.
  Innovation update(const Measurement& z) { return derived().update_all(z, nullptr); }

  // Multirate update: only the rows of z marked in `present` (the others are ignored, whatever
  // their value). An empty mask leaves the estimate as it is and returns dimension 0.
  // @param z measurement (M); @param present rows of z that arrived.
  // @param considered consider states: not corrected (see measurement_update.h).
  Innovation update(const Measurement& z, const MeasurementMask<M>& present,
                    const StateMask<N>& considered = StateMask<N>()) {
    if (present.all()) return derived().update_all(z, &considered);
    if (present.none()) return Innovation{std::numeric_limits<double>::quiet_NaN(), 0};
    const MeasurementSubset<N, M> s = derived().subset(z, present);
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

 protected:
  // @param x0 initial estimate (N); @param P0 its covariance (N x N), symmetric PSD.
  KalmanFilterBase(const Model& model, const State& x0, const StateMatrix& P0,
                   const FilterOptions& options)
      : model_(model), x_(x0), P_(P0), options_(options) {}

  // P- = F P+ F^T + Q_d (000 eq. 4.6), its upper triangle mirrored so that P stays exactly
  // symmetric when no measurement follows. add_noise(P) adds Q_d to P (it reads x+, so call this
  // before x moves to x-).
  // @param F state transition or its Jacobian J_f_x at (x+, u) (N x N).
  template <class AddNoise>
  void predict_covariance(const StateMatrix& F, AddNoise&& add_noise) {
    const StateMatrix FP = F * P_;
    P_.noalias() = FP * F.transpose();
    add_noise(P_);
    P_.template triangularView<Eigen::StrictlyLower>() = P_.transpose();
  }

  // The update with every row (measurement_update.h).
  // @param nu innovation z - h(x-) (M); @param H measurement matrix or J_h_x at x- (M x N);
  // @param R (M x M); @param considered consider states (nullptr: none).
  Innovation update_with(const Measurement& nu, const Matrix<M, N>& H, const Matrix<M, M>& R,
                         const StateMask<N>* considered) {
    return measurement_update<N, M, M>(nu, H, R, considered, options_.covariance_update, x_, P_);
  }

  Model model_;
  State x_;
  StateMatrix P_;
  FilterOptions options_;

 private:
  Derived& derived() { return static_cast<Derived&>(*this); }
};

}  // namespace kalman
}  // namespace chatterlab
