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
// is measurement_update.h (LDLT of S, consider states, NIS), shared with KalmanFilter.
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
class ExtendedKalmanFilter {
 public:
  static constexpr int N = Model::kStates;
  static constexpr int M = Model::kMeasurements;
  using State = typename Model::State;
  using Input = typename Model::Input;
  using Measurement = typename Model::Measurement;
  using StateMatrix = Matrix<N, N>;
  using MeasurementJacobian = Matrix<M, N>;

  // @param model the process and measurement model (see above).
  // @param x0 initial estimate x+_0 (N).
  // @param P0 its covariance (N x N), symmetric positive semi-definite.
  ExtendedKalmanFilter(const Model& model, const State& x0, const StateMatrix& P0,
                       const FilterOptions& options = {})
      : model_(model), x_(x0), P_(P0), options_(options) {}

  // @param u input u_k-1 of f.
  void predict(const Input& u) {
    StateMatrix F;
    const State x_prior = model_.propagate(x_, u, &F);
    const StateMatrix FP = F * P_;
    P_.noalias() = FP * F.transpose();
    model_.add_process_noise(x_, &P_);
    P_.template triangularView<Eigen::StrictlyLower>() = P_.transpose();
    x_ = x_prior;
  }

  // @param z measurement z_k (M), every row present.
  Innovation update(const Measurement& z) { return update_rows(z, nullptr); }

  // Schmidt update: the states in `considered` keep their estimates (their gain rows are zero);
  // the covariance is the exact one of that gain (measurement_update.h).
  // @param z measurement (M); @param considered consider states.
  Innovation update_consider(const Measurement& z, const StateMask<N>& considered) {
    return update_rows(z, &considered);
  }

  // Multirate update: only the rows of z marked in `present` (the rest are ignored). An empty
  // mask leaves the estimate as it is and returns dimension 0.
  // @param z measurement (M); @param present rows that arrived; @param considered consider states.
  Innovation update(const Measurement& z, const MeasurementMask<M>& present,
                    const StateMask<N>& considered = StateMask<N>()) {
    if (present.all()) return update_rows(z, &considered);
    if (present.none()) return Innovation{std::numeric_limits<double>::quiet_NaN(), 0};
    MeasurementJacobian H;
    const Measurement h = model_.measure(x_, &H);
    const MeasurementSubset<N, M> s(z, h, H, model_.measurement_noise(), present);
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
  Innovation update_rows(const Measurement& z, const StateMask<N>* considered) {
    const Matrix<M, M>& R = model_.measurement_noise();
    if constexpr (SelectsStates<Model>::value) {
      // P- H^T and S are selections of P-; the constant H (for the Joseph form) is H_.
      const Measurement nu = z - model_.measure(x_, nullptr);
      Matrix<N, M> PHt;
      Matrix<M, M> S;
      for (int i = 0; i < M; ++i) PHt.col(i) = P_.col(Model::measured_state(i));
      for (int i = 0; i < M; ++i) {
        for (int j = 0; j < M; ++j) S(i, j) = PHt(Model::measured_state(i), j) + R(i, j);
      }
      return gain_update<N, M, M>(nu, PHt, S, H_, R, considered, options_.covariance_update, x_,
                                  P_);
    } else {
      MeasurementJacobian H;
      const Measurement nu = z - model_.measure(x_, &H);
      return measurement_update<N, M, M>(nu, H, R, considered, options_.covariance_update, x_, P_);
    }
  }

  static MeasurementJacobian selection() {
    MeasurementJacobian H = MeasurementJacobian::Zero();
    if constexpr (SelectsStates<Model>::value) {
      for (int i = 0; i < M; ++i) H(i, Model::measured_state(i)) = 1.0;
    }
    return H;
  }

  Model model_;
  State x_;
  StateMatrix P_;
  FilterOptions options_;
  MeasurementJacobian H_ = selection();  // H of a selecting model (zero otherwise, unused)
};

}  // namespace kalman
}  // namespace chatterlab
