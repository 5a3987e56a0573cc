#include "analysis/metrics/metrics.h"

#include <cmath>
#include <string>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace metrics {
namespace {

void check_pair(Eigen::Index ny, Eigen::Index nyhat, Eigen::Index min_size, const char* what) {
  if (ny != nyhat) {
    throw InputError(std::string(what) + ": y has " + std::to_string(ny) + " values, yhat " +
                     std::to_string(nyhat) + ": must be equal");
  }
  if (ny < min_size) {
    throw InputError(std::string(what) + ": y has " + std::to_string(ny) +
                     " values: needs at least " + std::to_string(min_size));
  }
}

template <typename Vec>
double rmse_impl(const Vec& y, const Vec& yhat) {
  check_pair(y.size(), yhat.size(), 1, "rmse");
  return std::sqrt((y - yhat).squaredNorm() / static_cast<double>(y.size()));
}

// 004 eq. 3.2.
template <typename Vec>
double fit_impl(const Vec& y, const Vec& yhat) {
  check_pair(y.size(), yhat.size(), 2, "nrmse_fit_pct");
  const double spread = (y.array() - y.mean()).matrix().norm();
  if (!(spread > 0.0)) {
    throw InputError("nrmse_fit_pct: ||y - mean(y)|| = " + std::to_string(spread) +
                     ": y must not be constant");
  }
  return 100.0 * (1.0 - (y - yhat).norm() / spread);
}

}  // namespace

double rmse(const Eigen::Ref<const Eigen::VectorXd>& y,
            const Eigen::Ref<const Eigen::VectorXd>& yhat) {
  return rmse_impl(y, yhat);
}

double rmse(const Eigen::Ref<const Eigen::VectorXcd>& y,
            const Eigen::Ref<const Eigen::VectorXcd>& yhat) {
  return rmse_impl(y, yhat);
}

double nrmse_fit_pct(const Eigen::Ref<const Eigen::VectorXd>& y,
                     const Eigen::Ref<const Eigen::VectorXd>& yhat) {
  return fit_impl(y, yhat);
}

double nrmse_fit_pct(const Eigen::Ref<const Eigen::VectorXcd>& y,
                     const Eigen::Ref<const Eigen::VectorXcd>& yhat) {
  return fit_impl(y, yhat);
}

double percent_error(double estimate, double reference) {
  if (!std::isfinite(estimate) || !std::isfinite(reference)) {
    throw InputError("percent_error: estimate = " + std::to_string(estimate) +
                     ", reference = " + std::to_string(reference) + ": both must be finite");
  }
  if (reference == 0.0) throw InputError("percent_error: reference = 0: must be non-zero");
  return 100.0 * (estimate - reference) / std::abs(reference);
}

}  // namespace metrics
}  // namespace chatterlab
