#include "analysis/dynamics/poincare.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

#include "analysis/common/summary.h"
#include "analysis/dynamics/local_spread.h"

namespace chatterlab {
namespace dynamics {

namespace {

void check_run(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
               const Eigen::Ref<const Eigen::VectorXd>& x_m, const PoincareMapOptions& o) {
  if (o.revolutions < 2) {
    std::ostringstream m;
    m << "poincare.revolutions = " << o.revolutions << ": must be >= 2";
    throw InputError(m.str());
  }
  if (depth_m.size() != x_m.size()) {
    std::ostringstream m;
    m << "poincare: depth_m has " << depth_m.size() << " revolutions, x_m " << x_m.size()
      << ": must be equal";
    throw InputError(m.str());
  }
  if (x_m.size() < o.revolutions + 1) {
    std::ostringstream m;
    m << "poincare: run has " << x_m.size()
      << " revolutions: a map of revolutions = " << o.revolutions << " needs " << o.revolutions + 1;
    throw InputError(m.str());
  }
}

PoincareMap map_around(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                       const Eigen::Ref<const Eigen::VectorXd>& x_m, Eigen::Index centre, int r) {
  const Eigen::Index n = x_m.size();
  PoincareMap map;
  map.centre_revolution = centre;
  map.first_revolution = std::clamp<Eigen::Index>(centre - r / 2, 1, n - r);
  map.first_depth_m = depth_m[map.first_revolution];
  map.last_depth_m = depth_m[map.first_revolution + r - 1];
  map.points_m.resize(r, 2);
  map.points_m.col(0) = x_m.segment(map.first_revolution - 1, r);
  map.points_m.col(1) = x_m.segment(map.first_revolution, r);
  return map;
}

}  // namespace

PoincareMap poincare_map(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                         const Eigen::Ref<const Eigen::VectorXd>& x_m, double depth,
                         const PoincareMapOptions& options) {
  check_run(depth_m, x_m, options);
  const double lo = depth_m.minCoeff();
  const double hi = depth_m.maxCoeff();
  // 1 nm of slack: a depth record computed as start + (end - start) n / (N - 1) may miss its
  // stated end by a rounding error.
  constexpr double kSlack = 1e-9;
  if (!(depth >= lo - kSlack && depth <= hi + kSlack)) {
    std::ostringstream m;
    m << "poincare: depth " << depth * 1e3 << " mm: outside the run's depths [" << lo * 1e3 << ", "
      << hi * 1e3 << "] mm";
    throw InputError(m.str());
  }
  Eigen::Index centre = 0;
  (depth_m.array() - depth).abs().minCoeff(&centre);
  PoincareMap map = map_around(depth_m, x_m, centre, options.revolutions);
  map.requested_depth_m = depth;
  return map;
}

std::vector<PoincareMap> poincare_maps(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                       const std::vector<double>& depths,
                                       const PoincareMapOptions& options) {
  std::vector<PoincareMap> maps;
  maps.reserve(depths.size());
  for (double d : depths) maps.push_back(poincare_map(depth_m, x_m, d, options));
  return maps;
}

PoincareMap poincare_map_at_revolution(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                       Eigen::Index centre_revolution,
                                       const PoincareMapOptions& options) {
  check_run(depth_m, x_m, options);
  if (centre_revolution < 0 || centre_revolution >= x_m.size()) {
    std::ostringstream m;
    m << "poincare: centre_revolution = " << centre_revolution << ": must be in [0, "
      << x_m.size() - 1 << "]";
    throw InputError(m.str());
  }
  return map_around(depth_m, x_m, centre_revolution, options.revolutions);
}

OrbitClass classify_orbit(const PoincareMap& map, double noise_floor_m,
                          const OrbitClassOptions& options) {
  if (!(noise_floor_m > 0.0)) {
    std::ostringstream m;
    m << "orbit class: noise_floor_m = " << noise_floor_m << ": must be > 0";
    throw InputError(m.str());
  }
  const Eigen::Index r = map.points_m.rows();
  if (r < 3) {
    std::ostringstream m;
    m << "orbit class: map has " << r << " points: at least 3 needed";
    throw InputError(m.str());
  }
  // The R + 1 samples x_(first-1) .. x_(first+R-1).
  Eigen::VectorXd x(r + 1);
  x[0] = map.points_m(0, 0);
  x.tail(r) = map.points_m.col(1);

  OrbitClass out;
  out.spread_m = detrended_spread(x);
  if (out.spread_m <= options.fixed_point_factor * noise_floor_m) {
    out.shape = OrbitShape::kFixedPoint;
    out.period = 1;
    return out;
  }
  const double cluster_limit = std::max(options.fixed_point_factor * std::sqrt(2.0) * noise_floor_m,
                                        options.cluster_tolerance * out.spread_m);
  for (int p = 2; p <= options.max_cluster_period && p + 2 <= x.size(); ++p) {
    // x_n - x_(n-p) about its mean: a slow drift only shifts it by p times its slope.
    Eigen::VectorXd d = x.tail(x.size() - p) - x.head(x.size() - p);
    d.array() -= d.mean();
    if (quartile_scale(d) <= cluster_limit) {
      out.shape = OrbitShape::kClusters;
      out.period = p;
      return out;
    }
  }
  // Quasi-periodic: x_n = F(theta_0 + 2 pi nu n) for a smooth periodic F, so that sorted by the
  // phase frac(nu n) the samples trace F smoothly (phase dispersion minimisation, Stellingwerf
  // 1978). The ordering changes only where frac(nu n) = frac(nu m), at fractions k / d with
  // d <= R: a grid of step 1 / (4 R^2) over (0, 1/2] visits every ordering.
  const double variance = (x.array() - x.mean()).square().sum();
  std::vector<std::pair<double, double>> phased(static_cast<std::size_t>(x.size()));
  const int steps = static_cast<int>(2 * (x.size() - 1) * (x.size() - 1));
  double best = std::numeric_limits<double>::infinity();
  for (int g = 1; g <= steps; ++g) {
    const double nu = 0.5 * g / steps;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      const double phase = nu * static_cast<double>(k);
      phased[static_cast<std::size_t>(k)] = {phase - std::floor(phase), x[k]};
    }
    std::sort(phased.begin(), phased.end());
    double sum = 0.0;
    for (std::size_t k = 0; k < phased.size(); ++k) {
      const double d = phased[(k + 1) % phased.size()].second - phased[k].second;
      sum += d * d;
    }
    best = std::min(best, sum / (2.0 * variance));
  }
  out.phase_dispersion = best;
  out.shape = best <= options.ring_phase_dispersion ? OrbitShape::kRing : OrbitShape::kCloud;
  return out;
}

const char* to_string(OrbitShape shape) {
  switch (shape) {
    case OrbitShape::kFixedPoint:
      return "fixed point";
    case OrbitShape::kClusters:
      return "clusters";
    case OrbitShape::kRing:
      return "ring";
    case OrbitShape::kCloud:
      return "cloud";
  }
  return "?";
}

}  // namespace dynamics
}  // namespace chatterlab
