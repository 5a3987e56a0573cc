#include "analysis/sysid/state_space.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace sysid {

Eigen::VectorXcd frequency_response(const DiscreteStateSpace& model,
                                    const Eigen::Ref<const Eigen::VectorXd>& f_hz) {
  const Eigen::Index n = model.order();
  Eigen::VectorXcd G(f_hz.size());
  const Eigen::MatrixXcd Ac = model.A.cast<std::complex<double>>();
  const Eigen::VectorXcd Bc = model.B.cast<std::complex<double>>();
  Eigen::MatrixXcd M(n, n);
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu(n);
  for (Eigen::Index i = 0; i < f_hz.size(); ++i) {
    const std::complex<double> z = std::polar(1.0, kTwoPi * f_hz[i] / model.sample_rate_hz);
    if (n == 0) {
      G[i] = model.D;
      continue;
    }
    M = -Ac;
    M.diagonal().array() += z;
    lu.compute(M);
    G[i] = (model.C.cast<std::complex<double>>() * lu.solve(Bc))(0) + model.D;
  }
  return G;
}

double dc_gain(const DiscreteStateSpace& model) {
  if (model.order() == 0) return model.D;
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(model.order(), model.order()) - model.A;
  return (model.C * M.partialPivLu().solve(model.B))(0) + model.D;
}

Eigen::VectorXcd poles(const DiscreteStateSpace& model) {
  if (model.order() == 0) return Eigen::VectorXcd();
  return Eigen::EigenSolver<Eigen::MatrixXd>(model.A, false).eigenvalues();
}

std::vector<DiscreteMode> modes_of(const Eigen::Ref<const Eigen::VectorXcd>& p,
                                   double sample_rate_hz) {
  std::vector<DiscreteMode> out;
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    if (!(p[i].imag() > 0.0) || std::abs(p[i]) == 0.0) continue;
    const std::complex<double> s = sample_rate_hz * std::log(p[i]);
    DiscreteMode m;
    m.z = p[i];
    m.fn_hz = std::abs(s) / kTwoPi;
    m.zeta = -s.real() / std::abs(s);
    out.push_back(m);
  }
  std::sort(out.begin(), out.end(),
            [](const DiscreteMode& a, const DiscreteMode& b) { return a.fn_hz < b.fn_hz; });
  return out;
}

}  // namespace sysid
}  // namespace chatterlab
