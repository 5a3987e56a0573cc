// Types shared by the filters of analysis/kalman: fixed-size matrix aliases, the masks of a
// measurement update, the covariance-update form and the innovation statistics of one update.
#pragma once

#include <Eigen/Core>
#include <bitset>
#include <cstddef>
#include <limits>

namespace chatterlab {
namespace kalman {

// Eigen matrix of double with storage order chosen as Eigen's default would be for these sizes
// (row-major for a single row), so that a vector with a compile-time maximum size (Rows =
// Eigen::Dynamic, MaxRows = M) lives on the stack: no heap allocation.
template <int Rows, int Cols, int MaxRows = Rows, int MaxCols = Cols>
using Matrix = Eigen::Matrix<double, Rows, Cols,
                             ((MaxRows == 1 && MaxCols != 1) ? Eigen::RowMajor : Eigen::ColMajor) |
                                 Eigen::AutoAlign,
                             MaxRows, MaxCols>;

// Bit i set: measurement row i is present at this update (multirate filters: a slow channel
// joins the update only at the steps where it arrives).
template <int M>
using MeasurementMask = std::bitset<static_cast<std::size_t>(M)>;

// Bit i set: state i is a "consider" state at this update (Schmidt-Kalman filter): its gain row
// is zero, so its estimate is not corrected, while its covariance with the corrected states is
// updated exactly for that suboptimal gain.
template <int N>
using StateMask = std::bitset<static_cast<std::size_t>(N)>;

// P := (P + P^T) / 2, over the upper triangle (the diagonal is unchanged).
template <int N>
void symmetrize(Matrix<N, N>& P) {
  for (int j = 1; j < N; ++j) {
    for (int i = 0; i < j; ++i) {
      const double v = 0.5 * (P(i, j) + P(j, i));
      P(i, j) = v;
      P(j, i) = v;
    }
  }
}

template <int M>
MeasurementMask<M> all_rows() {
  return MeasurementMask<M>().set();
}

enum class CovarianceUpdate {
  // P+ = P- - K H P- (000 eq. 4.9), its upper triangle mirrored (K H P- is symmetric in exact
  // arithmetic); with consider states, P- - A with A = K_opt H P-
  // except A's consider-consider block, which is zero (the exact covariance of that gain).
  kStandard,
  // Joseph form P+ = (I - K H) P- (I - K H)^T + K R K^T, symmetrised: the covariance of the gain
  // actually applied whatever it is, a sum of positive semi-definite terms.
  kJoseph,
};

struct FilterOptions {
  // Form of the covariance update. The two agree for the optimal gain to rounding; the Joseph
  // form costs two more N x N products and keeps P positive semi-definite under rounding when
  // the update shrinks P by many orders of magnitude.
  CovarianceUpdate covariance_update = CovarianceUpdate::kStandard;
};

// Statistics of one measurement update. Default: no update (NaN).
struct Innovation {
  // Normalized innovation squared nu^T S^-1 nu, nu = z - h(x-), S = H P- H^T + R. For a
  // consistent filter it is chi-square distributed with `dimension` degrees of freedom.
  double nis = std::numeric_limits<double>::quiet_NaN();
  int dimension = 0;  // rows of z in the update
};

}  // namespace kalman
}  // namespace chatterlab
