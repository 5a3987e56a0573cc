#include "analysis/sysid/random_system.h"

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"

namespace chatterlab {
namespace sysid {

DiscreteStateSpace random_stable_system(const RandomSystemOptions& o, double rate,
                                        std::uint64_t seed) {
  require_rule(o.order >= 1, "order", o.order, "must be >= 1");
  require_rule(o.complex_fraction >= 0.0 && o.complex_fraction <= 1.0, "complex_fraction",
               o.complex_fraction, "must be in [0, 1]");
  require_rule(o.min_radius > 0.0 && o.min_radius <= o.max_radius && o.max_radius < 1.0,
               "radius range", std::to_string(o.min_radius) + " .. " + std::to_string(o.max_radius),
               "must satisfy 0 < min <= max < 1");
  require_rule(o.min_angle > 0.0 && o.min_angle < 0.5 * kPi, "min_angle", o.min_angle,
               "must be in (0, pi/2)");
  require_rule(std::isfinite(rate) && rate > 0.0, "sample_rate_hz", rate, "must be > 0");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> radius(o.min_radius, o.max_radius);
  std::uniform_real_distribution<double> angle(o.min_angle, kPi - o.min_angle);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = o.order;
  const int pairs = std::min(n / 2, static_cast<int>(std::lround(0.5 * o.complex_fraction * n)));
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  int k = 0;
  for (int p = 0; p < pairs; ++p, k += 2) {
    const double r = radius(rng);
    const double th = angle(rng);
    A(k, k) = r * std::cos(th);
    A(k, k + 1) = -r * std::sin(th);
    A(k + 1, k) = r * std::sin(th);
    A(k + 1, k + 1) = r * std::cos(th);
  }
  for (; k < n; ++k) A(k, k) = (unit(rng) < 0.5 ? -1.0 : 1.0) * radius(rng);
  Eigen::MatrixXd X(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) X(i, j) = normal(rng);
  }
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(X).householderQ();
  DiscreteStateSpace s;
  s.sample_rate_hz = rate;
  s.A = Q * A * Q.transpose();
  s.B.resize(n);
  s.C.resize(n);
  for (int i = 0; i < n; ++i) s.B[i] = normal(rng);
  for (int i = 0; i < n; ++i) s.C[i] = normal(rng);
  s.D = o.d_scale * normal(rng);
  return s;
}

}  // namespace sysid
}  // namespace chatterlab
