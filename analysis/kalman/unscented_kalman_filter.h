// Unscented Kalman filter with additive noise over the model interface of
// ExtendedKalmanFilter (extended_kalman_filter.h), after Julier, "The scaled unscented
// transformation", Proc. American Control Conference (2002) 4555-4559, and Wan, van der Merwe,
// "The unscented Kalman filter for nonlinear estimation", IEEE AS-SPCC (2000) 153-158:
//
//   sigma points of (x, P), n = N states:  lambda = alpha^2 (n + kappa) - n
//     chi_0 = x,  chi_i = x + s_i,  chi_n+i = x - s_i   (s_i: column i of sqrt((n + lambda) P))
//     Wm_0 = lambda / (n + lambda),  Wc_0 = Wm_0 + 1 - alpha^2 + beta,
//     Wm_i = Wc_i = 1 / (2 (n + lambda))
//   predict:  Y_i = f(chi_i, u) from the sigma points of (x+, P+)
//             x- = sum Wm_i Y_i,  P- = sum Wc_i (Y_i - x-)(Y_i - x-)^T + Q_d(x+)
//   update:   Z_i = h(chi_i) from the sigma points of (x-, P-)
//             z^ = sum Wm_i Z_i,  P_zz = sum Wc_i (Z_i - z^)(Z_i - z^)^T,
//             P_xz = sum Wc_i (chi_i - x-)(Z_i - z^)^T,  S = P_zz + R
//             K = P_xz S^-1,  x+ = x- + K (z - z^),  P+ = P- - K S K^T
//
// The update is gain_update of measurement_update.h with P_xz in place of P- H^T (so consider
// states and the NIS are those of the other filters); the Joseph form needs H and is not used.
// The square root is taken of the correlation matrix, sqrt(P) = D chol(D^-1 P D^-1) with D the
// standard deviations, because the states span many orders of magnitude (a deflection of 1e-5 m
// beside a cutting coefficient of 1e9 N/m^2: P's condition number reaches 1e30). Deviations are
// formed from the image of the centre, Y_i - Y_0, before they are averaged, so that a large
// state does not round away a small spread.
//
// A model whose h selects states (measured_state) has a linear h, for which the unscented
// transform is exact: P_xz and P_zz are then read from P- directly (the same numbers to
// rounding; tests/analysis/kalman/kalman_unscented_test.cpp compares the two paths).
//
// Fixed sizes throughout: nothing here allocates.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "analysis/kalman/extended_kalman_filter.h"
#include "analysis/kalman/filter_base.h"
#include "analysis/kalman/filter_types.h"
#include "analysis/kalman/measurement_update.h"

namespace chatterlab {
namespace kalman {

// Spread and weights of the scaled sigma points. Defaults alpha = 1, beta = 2, kappa = 0:
// lambda = 0, the points at +-sqrt(n) standard deviations, Wm_0 = 0 and Wc_0 = 2, every weight
// positive (a small alpha such as 1e-3 puts the points at 1e-3 sqrt(n) standard deviations
// with Wc_0 near -1e6, which loses the covariance to rounding on states of 1e-5 and 1e9 at
// once).
struct UnscentedOptions {
  double alpha = 1.0;  // > 0
  double beta = 2.0;   // 2 is optimal for a Gaussian prior
  double kappa = 0.0;  // n + kappa > 0

  // n + lambda = alpha^2 (n + kappa): the squared spread of the points in standard deviations.
  double spread2(int n) const { return alpha * alpha * (n + kappa); }
};

// Throws std::invalid_argument naming the field when the points are not defined for n states.
inline void validate(const UnscentedOptions& o, int n) {
  if (!(std::isfinite(o.alpha) && o.alpha > 0.0)) {
    throw std::invalid_argument("ukf.alpha = " + std::to_string(o.alpha) + ": must be > 0");
  }
  if (!std::isfinite(o.beta)) throw std::invalid_argument("ukf.beta: must be finite");
  if (!(std::isfinite(o.kappa) && n + o.kappa > 0.0)) {
    throw std::invalid_argument("ukf.kappa = " + std::to_string(o.kappa) +
                                ": n + kappa must be > 0 (n = " + std::to_string(n) + ")");
  }
}

template <class Model>
class UnscentedKalmanFilter : public KalmanFilterBase<UnscentedKalmanFilter<Model>, Model,
                                                      Model::kStates, Model::kMeasurements> {
  using Base =
      KalmanFilterBase<UnscentedKalmanFilter<Model>, Model, Model::kStates, Model::kMeasurements>;
  friend Base;

 public:
  static constexpr int N = Model::kStates;
  static constexpr int M = Model::kMeasurements;
  using typename Base::Measurement;
  using typename Base::State;
  using typename Base::StateMatrix;
  using Input = typename Model::Input;

  // @param model the process and measurement model (extended_kalman_filter.h; the Jacobian
  // arguments are passed null). @param x0, P0 initial estimate and its covariance (positive
  // definite). @param options the sigma points (validated: std::invalid_argument).
  // The base's estimate, accessors and update(z) are shared with the other filters; its
  // multirate update(z, present) is not provided (it needs a measurement subset of sigma points).
  UnscentedKalmanFilter(const Model& model, const State& x0, const StateMatrix& P0,
                        const UnscentedOptions& options = {})
      : Base(model, x0, P0, FilterOptions{}) {
    validate(options, N);
    const double c = options.spread2(N);
    const double lambda = c - N;
    scale_ = std::sqrt(c);
    wm0_ = lambda / c;
    wc0_ = wm0_ + 1.0 - options.alpha * options.alpha + options.beta;
    wi_ = 0.5 / c;
  }

  // @param u input u_k-1 of f.
  void predict(const Input& u) {
    Matrix<N, N> S;
    if (!square_root(S)) return poison();
    const State y0 = this->model_.propagate(this->x_, u, nullptr);
    Matrix<N, 2 * N> dY;
    for (int i = 0; i < N; ++i) {
      dY.col(i) = this->model_.propagate(this->x_ + S.col(i), u, nullptr) - y0;
      dY.col(N + i) = this->model_.propagate(this->x_ - S.col(i), u, nullptr) - y0;
    }
    // The mean's offset from Y_0; Y_0 - x- = -dm.
    const State dm = wi_ * dY.rowwise().sum();
    StateMatrix P = wc0_ * dm * dm.transpose();
    dY.colwise() -= dm;
    P.noalias() += wi_ * dY * dY.transpose();
    this->model_.add_process_noise(this->x_, &P);  // Q_d at x+
    P.template triangularView<Eigen::StrictlyLower>() = P.transpose();
    this->x_ = y0 + dm;
    this->P_ = P;
  }

  // Schmidt update: the states in `considered` keep their estimates (measurement_update.h).
  Innovation update_consider(const Measurement& z, const StateMask<N>& considered) {
    return update_all(z, &considered);
  }

 private:
  Innovation update_all(const Measurement& z, const StateMask<N>* considered) {
    const Matrix<M, M>& R = this->model_.measurement_noise();
    Matrix<N, M> Pxz;
    Matrix<M, M> S;
    Measurement nu;
    if constexpr (SelectsStates<Model>::value) {
      nu = z - this->model_.measure(this->x_, nullptr);
      for (int i = 0; i < M; ++i) Pxz.col(i) = this->P_.col(Model::measured_state(i));
      for (int i = 0; i < M; ++i) {
        for (int j = 0; j < M; ++j) S(i, j) = Pxz(Model::measured_state(i), j) + R(i, j);
      }
    } else {
      Matrix<N, N> L;
      if (!square_root(L)) {
        poison();
        return Innovation{};
      }
      const Measurement z0 = this->model_.measure(this->x_, nullptr);
      Matrix<M, 2 * N> dZ;
      Matrix<N, 2 * N> dX;
      for (int i = 0; i < N; ++i) {
        dZ.col(i) = this->model_.measure(this->x_ + L.col(i), nullptr) - z0;
        dZ.col(N + i) = this->model_.measure(this->x_ - L.col(i), nullptr) - z0;
        dX.col(i) = L.col(i);
        dX.col(N + i) = -L.col(i);
      }
      const Measurement dm = wi_ * dZ.rowwise().sum();  // z^ - Z_0
      dZ.colwise() -= dm;
      // The x deviations have zero weighted mean (symmetric points), and chi_0 - x- = 0.
      Pxz.noalias() = wi_ * dX * dZ.transpose();
      S = wc0_ * dm * dm.transpose() + R;
      S.noalias() += wi_ * dZ * dZ.transpose();
      nu = z - (z0 + dm);
    }
    return gain_update<N, M, M>(nu, Pxz, S, Matrix<M, N>::Zero(), R, considered,
                                CovarianceUpdate::kStandard, this->x_, this->P_);
  }

  // S = sqrt((n + lambda) P) = scale D chol(D^-1 P D^-1), lower triangular; false when P is not
  // positive definite.
  bool square_root(Matrix<N, N>& S) const {
    State d;
    for (int i = 0; i < N; ++i) {
      if (!(this->P_(i, i) > 0.0) || !std::isfinite(this->P_(i, i))) return false;
      d[i] = std::sqrt(this->P_(i, i));
    }
    const State inv_d = d.cwiseInverse();
    const Matrix<N, N> C = inv_d.asDiagonal() * this->P_ * inv_d.asDiagonal();
    const Eigen::LLT<Matrix<N, N>> llt(C);
    if (llt.info() != Eigen::Success) return false;
    S = (scale_ * d).asDiagonal() * llt.matrixL().toDenseMatrix();
    return true;
  }

  // The estimate becomes NaN for the caller to see (P not positive definite).
  void poison() {
    this->x_.setConstant(std::numeric_limits<double>::quiet_NaN());
    this->P_.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

  double scale_ = 1.0;  // sqrt(n + lambda)
  double wm0_ = 0.0;
  double wc0_ = 0.0;
  double wi_ = 0.0;
};

}  // namespace kalman
}  // namespace chatterlab
