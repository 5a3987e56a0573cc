// Error measures between a reference y and an estimate yhat.
#pragma once

#include <Eigen/Core>

#include "analysis/common/summary.h"  // InputError

namespace chatterlab {
namespace metrics {

// Root-mean-square error sqrt(mean((y - yhat)^2)).
// @param y, yhat  same length, >= 1
// @throws InputError on empty or mismatched inputs
double rmse(const Eigen::Ref<const Eigen::VectorXd>& y,
            const Eigen::Ref<const Eigen::VectorXd>& yhat);
// Complex version: sqrt(mean(|y - yhat|^2)).
double rmse(const Eigen::Ref<const Eigen::VectorXcd>& y,
            const Eigen::Ref<const Eigen::VectorXcd>& yhat);

// NRMSE fit in percent, 004 eq. 3.2:
//   fit = 100 (1 - ||y - yhat|| / ||y - mean(y)||),
// 100 for a perfect fit, 0 for a fit no better than the mean, negative when worse.
// @param y     reference (measured) data, length >= 2, not constant
// @param yhat  model output, same length
// @throws InputError on empty or mismatched inputs or a constant y (||y - mean(y)|| = 0)
double nrmse_fit_pct(const Eigen::Ref<const Eigen::VectorXd>& y,
                     const Eigen::Ref<const Eigen::VectorXd>& yhat);
// Complex version (e.g. an FRF): mean(y) is the complex mean, norms are of complex
// differences, ||z|| = sqrt(sum |z_i|^2).
double nrmse_fit_pct(const Eigen::Ref<const Eigen::VectorXcd>& y,
                     const Eigen::Ref<const Eigen::VectorXcd>& yhat);

// Signed percent error 100 (estimate - reference) / |reference|.
// @throws InputError if reference is 0 or either value is not finite
double percent_error(double estimate, double reference);

}  // namespace metrics
}  // namespace chatterlab
