// The measurement update shared by KalmanFilter and ExtendedKalmanFilter (000 eqs 4.7-4.9, after
// Simon [55] of 000; M = I):
//
//   S   = H P- H^T + R                   innovation covariance (LDL^T, small_ldlt.h; not inverted)
//   K   = P- H^T S^-1                    gain
//   x+  = x- + K nu,   nu = z - h(x-)    (nu = z - H x- for a linear model)
//   P+  = P- - K H P-                    (CovarianceUpdate::kStandard; K H P- is symmetric, so
//                                         P+ takes its upper triangle, mirrored), or
//   P+  = (I - K H) P- (I - K H)^T + K R K^T   (kJoseph), then P+ = (P+ + P+^T) / 2.
//
// Consider states c (the Schmidt-Kalman filter): K's rows c are zero. The standard form then
// subtracts A = K_opt H P- with A's c-c block zero, which is the exact covariance of that
// suboptimal gain (it equals the Joseph form for it); the Joseph form applies as written.
//
// NIS = nu^T S^-1 nu (Bar-Shalom, Li, Kirubarajan, "Estimation with Applications to Tracking and
// Navigation", 2001, ch. 5: consistency of state estimators), from the same factorization of S.
//
// Sizes: N states, Rows innovation rows (fixed M, or Eigen::Dynamic with at most MaxRows for a
// measurement subset). Every temporary has a compile-time maximum size: no heap allocation.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/kalman/filter_types.h"
#include "analysis/kalman/small_ldlt.h"

namespace chatterlab {
namespace kalman {

// The update from P- H^T and S (measurement_update below forms them from H; a filter whose H
// selects states forms them by selection, and an unscented filter would pass its cross
// covariance P_xz and P_zz + R). H and R enter only the Joseph form.
// @param nu innovation z - h(x-) (Rows).
// @param PHt P- H^T (N x Rows).
// @param S innovation covariance H P- H^T + R (Rows x Rows), symmetric positive definite.
// @param H measurement matrix or Jacobian J_h_x at x- (Rows x N).
// @param R measurement noise covariance (Rows x Rows), symmetric positive definite.
// @param considered consider states (nullptr or none: every state is corrected).
// @param form covariance update form.
// @param x estimate x- in, x+ out (N).
// @param P covariance P- in, P+ out (N x N), symmetric positive semi-definite.
template <int N, int Rows, int MaxRows>
Innovation gain_update(const Matrix<Rows, 1, MaxRows, 1>& nu,
                       const Matrix<N, Rows, N, MaxRows>& PHt,
                       const Matrix<Rows, Rows, MaxRows, MaxRows>& S,
                       const Matrix<Rows, N, MaxRows, N>& H,
                       const Matrix<Rows, Rows, MaxRows, MaxRows>& R,
                       const StateMask<N>* considered, CovarianceUpdate form, Matrix<N, 1>& x,
                       Matrix<N, N>& P) {
  using Gain = Matrix<N, Rows, N, MaxRows>;
  Innovation out;
  out.dimension = static_cast<int>(nu.size());
  const SmallLdlt<Rows, MaxRows> ldlt(S);
  if (!ldlt.positive()) {
    // S = H P- H^T + R is not positive definite (P- lost definiteness, or R is not positive
    // definite): no update can be made, and the estimate becomes NaN for the caller to see.
    x.setConstant(std::numeric_limits<double>::quiet_NaN());
    P.setConstant(std::numeric_limits<double>::quiet_NaN());
    return out;
  }
  Gain K = PHt;
  ldlt.solve_right_in_place(K);  // K = P- H^T S^-1
  out.nis = ldlt.inverse_quadratic_form(nu);
  const bool consider = considered != nullptr && considered->any();
  const bool standard = form == CovarianceUpdate::kStandard;
  if (standard) {
    // P+ = P- - A, A = K_opt (P- H^T)^T with K_opt the optimal gain (every row) and A's
    // consider-consider block zero; A is symmetric, so P+ takes its upper triangle, mirrored.
    Matrix<N, N> A;
    A.noalias() = K * PHt.transpose();
    if (consider) {
      for (int j = 0; j < N; ++j) {
        if (!(*considered)[static_cast<std::size_t>(j)]) continue;
        for (int i = 0; i < N; ++i) {
          if ((*considered)[static_cast<std::size_t>(i)]) A(i, j) = 0.0;
        }
      }
    }
    P -= A;
    P.template triangularView<Eigen::StrictlyLower>() = P.transpose();
  }
  if (consider) {
    for (int i = 0; i < N; ++i) {
      if ((*considered)[static_cast<std::size_t>(i)]) K.row(i).setZero();
    }
  }
  x.noalias() += K * nu;
  if (!standard) {
    Matrix<N, N> I_KH = Matrix<N, N>::Identity();
    I_KH.noalias() -= K * H;
    const Matrix<N, N> IKH_P = I_KH * P;
    P.noalias() = IKH_P * I_KH.transpose();
    const Gain KR = K * R;
    P.noalias() += KR * K.transpose();
    symmetrize<N>(P);
  }
  return out;
}

// @param nu innovation z - h(x-) (Rows).
// @param H measurement matrix or Jacobian J_h_x at x- (Rows x N).
// @param R measurement noise covariance (Rows x Rows), symmetric positive definite.
// @param considered consider states (nullptr or none: every state is corrected).
// @param form covariance update form.
// @param x estimate x- in, x+ out (N).
// @param P covariance P- in, P+ out (N x N), symmetric positive semi-definite.
template <int N, int Rows, int MaxRows>
Innovation measurement_update(const Matrix<Rows, 1, MaxRows, 1>& nu,
                              const Matrix<Rows, N, MaxRows, N>& H,
                              const Matrix<Rows, Rows, MaxRows, MaxRows>& R,
                              const StateMask<N>* considered, CovarianceUpdate form,
                              Matrix<N, 1>& x, Matrix<N, N>& P) {
  Matrix<N, Rows, N, MaxRows> PHt;
  PHt.noalias() = P * H.transpose();
  Matrix<Rows, Rows, MaxRows, MaxRows> S = R;
  S.noalias() += H * PHt;
  return gain_update<N, Rows, MaxRows>(nu, PHt, S, H, R, considered, form, x, P);
}

// The rows of (z, h, H, R) marked in `present`, packed at the top of stack-allocated matrices
// with at most M rows.
template <int N, int M>
struct MeasurementSubset {
  Matrix<Eigen::Dynamic, 1, M, 1> nu;
  Matrix<Eigen::Dynamic, N, M, N> H;
  Matrix<Eigen::Dynamic, Eigen::Dynamic, M, M> R;

  // @param z measurement (M); @param h predicted measurement h(x-) (M); @param H_full (M x N);
  // @param R_full (M x M); @param present rows to keep.
  MeasurementSubset(const Matrix<M, 1>& z, const Matrix<M, 1>& h, const Matrix<M, N>& H_full,
                    const Matrix<M, M>& R_full, const MeasurementMask<M>& present) {
    const Eigen::Index m = static_cast<Eigen::Index>(present.count());
    nu.resize(m);
    H.resize(m, N);
    R.resize(m, m);
    Eigen::Index a = 0;
    for (int i = 0; i < M; ++i) {
      if (!present[static_cast<std::size_t>(i)]) continue;
      nu[a] = z[i] - h[i];
      H.row(a) = H_full.row(i);
      Eigen::Index b = 0;
      for (int j = 0; j < M; ++j) {
        if (present[static_cast<std::size_t>(j)]) R(a, b++) = R_full(i, j);
      }
      ++a;
    }
  }
};

}  // namespace kalman
}  // namespace chatterlab
