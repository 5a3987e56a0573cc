// Consistency diagnostics of a Kalman filter (Bar-Shalom, Li, Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", 2001, ch. 5). For a filter whose model and noise
// covariances match the data:
//   NIS_k  = nu_k^T S_k^-1 nu_k ~ chi-square(m_k)     (m_k rows in update k), independent over k;
//   NEES_k = e_k^T P_k^-1 e_k   ~ chi-square(N),      e_k = x_k - x+_k (needs the truth x_k).
// So the mean NIS of K updates has the band chi-square(sum m_k) / K, and each step's NIS the
// band of chi-square(m_k); a mean above the band says the filter is overconfident (Q or R too
// small, or a wrong model), below it underconfident. NEES samples of one step over independent
// runs average likewise (their time average is not chi-square: e_k is correlated in time).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include "analysis/kalman/chi_square.h"
#include "analysis/kalman/filter_types.h"

namespace chatterlab {
namespace kalman {

// NIS over a run. Default: nothing accumulated (NaN), so an empty summary never looks consistent.
struct NisSummary {
  std::int64_t updates = 0;  // updates with at least one measurement row
  std::int64_t dof = 0;      // sum of their dimensions
  double mean = std::numeric_limits<double>::quiet_NaN();  // mean NIS per update
  // Band of `mean` under consistency: chi-square(dof) / updates at `confidence` (two-sided).
  ChiSquareBand mean_band;
  // Fraction of updates whose NIS lies in the per-update band chi-square(m_k) (expected:
  // confidence).
  double fraction_inside = std::numeric_limits<double>::quiet_NaN();
  double confidence = 0.95;

  bool mean_inside() const { return updates > 0 && mean_band.contains(mean); }
  // "mean NIS 2.03 in [1.99, 2.01] (95 %), 94.8 % of 396000 updates inside their band".
  std::string report() const;
};

// Accumulates the NIS of updates with at most M rows; add() allocates nothing.
template <int M>
class NisMonitor {
 public:
  // @param confidence two-sided confidence of the bands, in (0, 1).
  explicit NisMonitor(double confidence = 0.95) : confidence_(confidence) {
    for (int m = 1; m <= M; ++m)
      step_band_[static_cast<std::size_t>(m)] = chi_square_band(m, confidence);
  }

  void add(const Innovation& i) {
    if (i.dimension <= 0) return;
    sum_ += i.nis;
    dof_ += i.dimension;
    ++updates_;
    if (step_band_[static_cast<std::size_t>(i.dimension)].contains(i.nis)) ++inside_;
  }

  // Pools another monitor's updates into this one (e.g. filters run side by side).
  void merge(const NisMonitor& o) {
    sum_ += o.sum_;
    dof_ += o.dof_;
    updates_ += o.updates_;
    inside_ += o.inside_;
  }

  // Solves the band of the mean (one quantile computation per call).
  NisSummary summary() const {
    NisSummary s;
    s.confidence = confidence_;
    s.updates = updates_;
    s.dof = dof_;
    if (updates_ == 0) return s;
    const double n = static_cast<double>(updates_);
    s.mean = sum_ / n;
    s.mean_band = mean_chi_square_band(n, static_cast<double>(dof_) / n, confidence_);
    s.fraction_inside = static_cast<double>(inside_) / n;
    return s;
  }

  // Band of one update with m rows, 1 <= m <= M.
  const ChiSquareBand& step_band(int m) const { return step_band_[static_cast<std::size_t>(m)]; }

 private:
  double confidence_;
  std::array<ChiSquareBand, static_cast<std::size_t>(M) + 1> step_band_{};
  double sum_ = 0.0;
  std::int64_t dof_ = 0;
  std::int64_t updates_ = 0;
  std::int64_t inside_ = 0;
};

// Means of the NIS over consecutive windows of `window` updates of `dimension` rows each (a
// trailing partial window is dropped), with the band of one window mean and the fraction of
// windows inside it.
struct NisWindows {
  Eigen::VectorXd mean;  // one per window
  ChiSquareBand band;    // chi-square(window dimension) / window
  double fraction_inside = std::numeric_limits<double>::quiet_NaN();
};

// @param nis per-update NIS (K); @param dimension rows per update, >= 1; @param window updates
// per window, 1 <= window <= K. Throws InputError naming the argument that breaks its rule.
NisWindows nis_windows(const Eigen::Ref<const Eigen::VectorXd>& nis, int dimension, int window,
                       double confidence = 0.95);

// e^T P^-1 e by LDLT of P. @param error x - x+ (N); @param P covariance (N x N), symmetric
// positive definite. Throws InputError for mismatched sizes.
double nees(const Eigen::Ref<const Eigen::VectorXd>& error,
            const Eigen::Ref<const Eigen::MatrixXd>& P);

}  // namespace kalman
}  // namespace chatterlab
