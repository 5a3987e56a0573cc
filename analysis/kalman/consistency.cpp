#include "analysis/kalman/consistency.h"

#include <Eigen/Cholesky>
#include <cstdio>

#include "analysis/common/require.h"

namespace chatterlab {
namespace kalman {

std::string NisSummary::report() const {
  if (updates == 0) return "no NIS: no update ran";
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "mean NIS %.4g %s [%.4g, %.4g] (%.0f %%), %.1f %% of %lld updates "
                "inside their band",
                mean, mean_inside() ? "in" : "outside", mean_band.lower, mean_band.upper,
                100.0 * confidence, 100.0 * fraction_inside, static_cast<long long>(updates));
  return buf;
}

NisWindows nis_windows(const Eigen::Ref<const Eigen::VectorXd>& nis, int dimension, int window,
                       double confidence) {
  require_rule(dimension >= 1, "nis_windows: dimension", dimension, "must be >= 1");
  require_rule(window >= 1 && window <= nis.size(), "nis_windows: window", window,
               "must be in [1, " + std::to_string(nis.size()) + "] (the number of updates)");
  NisWindows w;
  const Eigen::Index count = nis.size() / window;
  w.mean.resize(count);
  w.band = mean_chi_square_band(window, dimension, confidence);
  Eigen::Index inside = 0;
  for (Eigen::Index i = 0; i < count; ++i) {
    w.mean[i] = nis.segment(i * window, window).mean();
    if (w.band.contains(w.mean[i])) ++inside;
  }
  w.fraction_inside = static_cast<double>(inside) / static_cast<double>(count);
  return w;
}

double nees(const Eigen::Ref<const Eigen::VectorXd>& error,
            const Eigen::Ref<const Eigen::MatrixXd>& P) {
  require_rule(P.rows() == error.size() && P.cols() == error.size(), "nees: P size",
               std::to_string(P.rows()) + " x " + std::to_string(P.cols()),
               "must be " + std::to_string(error.size()) + " x " + std::to_string(error.size()) +
                   " (the error's size)");
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(P);
  return error.dot(ldlt.solve(error));
}

}  // namespace kalman
}  // namespace chatterlab
