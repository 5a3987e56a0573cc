#include "analysis/forcerec/model.h"

#include <Eigen/QR>
#include <cmath>
#include <stdexcept>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace forcerec {

namespace {

void check_shapes(Eigen::Index n, Eigen::Index cols, Eigen::Index b, Eigen::Index c) {
  if (n == 0 || cols != n) throw std::invalid_argument("forcerec model: A must be square, n >= 1");
  if (b != n) throw std::invalid_argument("forcerec model: B must have n rows");
  if (c != n) throw std::invalid_argument("forcerec model: C must have n columns");
}

}  // namespace

DiscreteModel zoh(const ContinuousModel& model, double sample_rate_hz) {
  const Eigen::Index n = model.A.rows();
  check_shapes(n, model.A.cols(), model.B.size(), model.C.size());
  if (!(sample_rate_hz > 0.0) || !std::isfinite(sample_rate_hz))
    throw std::invalid_argument("forcerec zoh: sample_rate_hz must be finite and > 0");
  const double dt = 1.0 / sample_rate_hz;
  // Van Loan: exp([[A, B], [0, 0]] dt) = [[Ad, Bd], [0, 1]] (004 eqs 2.2-2.3 with E1).
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 1, n + 1);
  M.topLeftCorner(n, n) = model.A * dt;
  M.topRightCorner(n, 1) = model.B * dt;
  const Eigen::MatrixXd E = M.exp();
  DiscreteModel out;
  out.Ad = E.topLeftCorner(n, n);
  out.Bd = E.topRightCorner(n, 1);
  out.C = model.C;
  out.sample_rate_hz = sample_rate_hz;
  return out;
}

Eigen::VectorXcd frequency_response(const ContinuousModel& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  const Eigen::Index n = model.A.rows();
  check_shapes(n, model.A.cols(), model.B.size(), model.C.size());
  const Eigen::MatrixXcd A = model.A.cast<std::complex<double>>();
  const Eigen::VectorXcd B = model.B.cast<std::complex<double>>();
  const Eigen::RowVectorXcd C = model.C.cast<std::complex<double>>();
  Eigen::VectorXcd out(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const std::complex<double> s(0.0, kTwoPi * f_hz[i]);
    const Eigen::MatrixXcd sI_A = s * Eigen::MatrixXcd::Identity(n, n) - A;
    out[i] = (C * sI_A.partialPivLu().solve(B))(0);
  }
  return out;
}

Eigen::VectorXcd frequency_response(const DiscreteModel& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  const Eigen::Index n = model.Ad.rows();
  check_shapes(n, model.Ad.cols(), model.Bd.size(), model.C.size());
  const Eigen::MatrixXcd A = model.Ad.cast<std::complex<double>>();
  const Eigen::VectorXcd B = model.Bd.cast<std::complex<double>>();
  const Eigen::RowVectorXcd C = model.C.cast<std::complex<double>>();
  Eigen::VectorXcd out(f_hz.size());
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const std::complex<double> z = std::polar(1.0, kTwoPi * f_hz[i] / model.sample_rate_hz);
    const Eigen::MatrixXcd zI_A = z * Eigen::MatrixXcd::Identity(n, n) - A;
    out[i] = (C * zI_A.partialPivLu().solve(B))(0);
  }
  return out;
}

Eigen::VectorXd impulse_response(const DiscreteModel& model, Eigen::Index count) {
  Eigen::VectorXd h(count);
  Eigen::VectorXd x = model.Bd, next(model.order());
  for (Eigen::Index k = 0; k < count; ++k) {
    h[k] = model.C.dot(x);
    next.noalias() = model.Ad * x;
    x.swap(next);
  }
  return h;
}

Eigen::VectorXd simulate(const DiscreteModel& model,
                         const Eigen::Ref<const Eigen::VectorXd>& force) {
  Eigen::VectorXd y(force.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.order()), next(model.order());
  for (Eigen::Index k = 0; k < force.size(); ++k) {
    y[k] = model.C.dot(x);
    next.noalias() = model.Ad * x;
    next += model.Bd * force[k];
    x.swap(next);
  }
  return y;
}

Eigen::MatrixXd orthogonal_complement(const Eigen::Ref<const Eigen::VectorXd>& c) {
  const Eigen::Index n = c.size();
  const Eigen::MatrixXd column = c;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(column);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, n);
  return Q.rightCols(n - 1);
}

}  // namespace forcerec
}  // namespace chatterlab
