// LDL^T factorization of the small symmetric positive definite innovation covariance S of a
// measurement update, S = L D L^T with L unit lower triangular and D diagonal (Golub, Van Loan,
// "Matrix Computations", 4th ed., alg. 4.1.2), and solves with it. No pivoting: S = H P H^T + R
// is positive definite when R is, and then the unpivoted factorization is as stable as
// Cholesky. Fixed sizes (or a compile-time maximum), no square roots and one division per pivot:
// for the 1 to 4 rows of a filter update the loops unroll, several times faster than
// Eigen::LDLT's pivoted blocked code.
#pragma once

#include <array>
#include <cstddef>

#include "analysis/kalman/filter_types.h"

namespace chatterlab {
namespace kalman {

template <int Rows, int MaxRows = Rows>
class SmallLdlt {
 public:
  using Square = Matrix<Rows, Rows, MaxRows, MaxRows>;

  // @param S symmetric (only its lower triangle is read), Rows x Rows.
  explicit SmallLdlt(const Square& S) : LD_(S) {
    const Eigen::Index m = S.rows();
    positive_ = true;
    for (Eigen::Index j = 0; j < m; ++j) {
      // LD_ holds L below the diagonal and D on it.
      double d = LD_(j, j);
      for (Eigen::Index k = 0; k < j; ++k) d -= LD_(j, k) * LD_(j, k) * LD_(k, k);
      LD_(j, j) = d;
      positive_ = positive_ && d > 0.0;
      const double inv_d = 1.0 / d;
      inv_d_[static_cast<std::size_t>(j)] = inv_d;
      for (Eigen::Index i = j + 1; i < m; ++i) {
        double s = LD_(i, j);
        for (Eigen::Index k = 0; k < j; ++k) s -= LD_(i, k) * LD_(j, k) * LD_(k, k);
        LD_(i, j) = s * inv_d;
      }
    }
  }

  // Every pivot d_j > 0 (S positive definite to working precision).
  bool positive() const { return positive_; }

  // B := S^-1 B. @param B right-hand sides (Rows x any).
  template <class Derived>
  void solve_in_place(Eigen::MatrixBase<Derived>& B) const {
    const Eigen::Index m = LD_.rows();
    for (Eigen::Index i = 1; i < m; ++i) {
      for (Eigen::Index k = 0; k < i; ++k) B.row(i) -= LD_(i, k) * B.row(k);
    }
    for (Eigen::Index i = 0; i < m; ++i) B.row(i) *= inv_d_[static_cast<std::size_t>(i)];
    for (Eigen::Index i = m - 2; i >= 0; --i) {
      for (Eigen::Index k = i + 1; k < m; ++k) B.row(i) -= LD_(k, i) * B.row(k);
    }
  }

  // B := B S^-1 = B L^-T D^-1 L^-1, column by column (a gain K = P H^T S^-1 in place of P H^T).
  // @param B (any x Rows).
  template <class Derived>
  void solve_right_in_place(Eigen::MatrixBase<Derived>& B) const {
    const Eigen::Index m = LD_.rows();
    for (Eigen::Index i = 1; i < m; ++i) {
      for (Eigen::Index k = 0; k < i; ++k) B.col(i) -= LD_(i, k) * B.col(k);
    }
    for (Eigen::Index i = 0; i < m; ++i) B.col(i) *= inv_d_[static_cast<std::size_t>(i)];
    for (Eigen::Index i = m - 2; i >= 0; --i) {
      for (Eigen::Index k = i + 1; k < m; ++k) B.col(i) -= LD_(k, i) * B.col(k);
    }
  }

  // v^T S^-1 v = sum_i y_i^2 / d_i with y = L^-1 v. @param v (Rows).
  double inverse_quadratic_form(const Matrix<Rows, 1, MaxRows, 1>& v) const {
    std::array<double, static_cast<std::size_t>(MaxRows)> y{};
    const Eigen::Index m = LD_.rows();
    double q = 0.0;
    for (Eigen::Index i = 0; i < m; ++i) {
      const std::size_t a = static_cast<std::size_t>(i);
      y[a] = v[i];
      for (Eigen::Index k = 0; k < i; ++k) y[a] -= LD_(i, k) * y[static_cast<std::size_t>(k)];
      q += y[a] * y[a] * inv_d_[a];
    }
    return q;
  }

 private:
  Square LD_;
  std::array<double, static_cast<std::size_t>(MaxRows)> inv_d_{};  // 1 / d_j: one division each
  bool positive_ = false;
};

}  // namespace kalman
}  // namespace chatterlab
