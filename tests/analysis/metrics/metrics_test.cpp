// Error measures against values computed by hand.
#include "analysis/metrics/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

namespace chatterlab {
namespace metrics {
namespace {

constexpr double kTol = 1e-12;  // closed forms: rounding only
using C = std::complex<double>;

TEST(Metrics, Rmse) {
  Eigen::VectorXd y(3), yhat(3);
  y << 1, 2, 3;
  yhat << 1, 2, 5;
  EXPECT_NEAR(rmse(y, yhat), std::sqrt(4.0 / 3.0), kTol);  // sqrt((0 + 0 + 4) / 3)
  Eigen::VectorXcd z(2), zhat(2);
  z << C(1, 1), C(0, 0);
  zhat << C(1, 0), C(3, 4);
  EXPECT_NEAR(rmse(z, zhat), std::sqrt((1.0 + 25.0) / 2.0), kTol);  // |i|^2 = 1, |3+4i|^2 = 25
}

TEST(Metrics, NrmseFitReal) {
  // 004 eq. 3.2: y = [1 2 3 4], mean 2.5, ||y - mean|| = sqrt(2.25 + 0.25 + 0.25 + 2.25) =
  // sqrt(5); yhat differs by 1 in one sample: fit = 100 (1 - 1/sqrt(5)) = 55.2786...
  Eigen::VectorXd y(4), yhat(4);
  y << 1, 2, 3, 4;
  yhat << 1, 2, 3, 5;
  EXPECT_NEAR(nrmse_fit_pct(y, yhat), 100.0 * (1.0 - 1.0 / std::sqrt(5.0)), kTol);
  EXPECT_NEAR(nrmse_fit_pct(y, y), 100.0, kTol);
  EXPECT_NEAR(nrmse_fit_pct(y, Eigen::VectorXd::Constant(4, 2.5)), 0.0, kTol);  // the mean: 0 %
}

TEST(Metrics, NrmseFitComplex) {
  // y = [1+i, 2+i, 3+i]: complex mean 2+i, ||y - mean|| = sqrt(1 + 0 + 1) = sqrt(2);
  // yhat = y + [0, 0.5i, 0]: ||y - yhat|| = 0.5: fit = 100 (1 - 0.5/sqrt(2)) = 64.6446...
  Eigen::VectorXcd y(3), yhat(3);
  y << C(1, 1), C(2, 1), C(3, 1);
  yhat << C(1, 1), C(2, 1.5), C(3, 1);
  EXPECT_NEAR(nrmse_fit_pct(y, yhat), 100.0 * (1.0 - 0.5 / std::sqrt(2.0)), kTol);
}

TEST(Metrics, PercentError) {
  EXPECT_NEAR(percent_error(105.0, 100.0), 5.0, kTol);
  EXPECT_NEAR(percent_error(0.03071, 0.03134), -2.0102105934907466,
              1e-10);                                     // (0.03071-0.03134)/0.03134
  EXPECT_NEAR(percent_error(-90.0, -100.0), 10.0, kTol);  // relative to |reference|
}

TEST(Metrics, BadInputIsRejected) {
  Eigen::VectorXd a(3), b(2);
  a << 1, 2, 3;
  b << 1, 2;
  try {
    rmse(a, b);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "rmse: y has 3 values, yhat 2: must be equal");
  }
  try {
    nrmse_fit_pct(Eigen::VectorXd::Constant(3, 1.0), a);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "nrmse_fit_pct: ||y - mean(y)|| = 0.000000: y must not be constant");
  }
  try {
    percent_error(1.0, 0.0);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "percent_error: reference = 0: must be non-zero");
  }
  EXPECT_THROW(rmse(Eigen::VectorXd(0), Eigen::VectorXd(0)), InputError);
}

}  // namespace
}  // namespace metrics
}  // namespace chatterlab
