// Poincare maps of once-per-revolution samples: x_n against x_(n-1) over a few revolutions at
// chosen depths (000 secs 5.2-5.3, "over twenty revolutions at axial depths of cut of 1 mm and
// 3 mm"), and a cheap reading of their shape: one point (chatter-free), clusters (period two,
// four, ...), a ring (quasi-periodic ellipse) or a cloud. docs/bifurcation.md sec. 5.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace chatterlab {
namespace dynamics {

struct PoincareMapOptions {
  // Points per map, R: the twenty revolutions of 000 Figs 5.1 and 5.7 (R + 1 samples).
  int revolutions = 20;
};

struct PoincareMap {
  double requested_depth_m = std::numeric_limits<double>::quiet_NaN();  // NaN: placed by index
  // The window is centred on this revolution: points n = centre - R/2 .. centre - R/2 + R - 1
  // (integer division), shifted inward when it would leave the run.
  Eigen::Index centre_revolution = 0;
  Eigen::Index first_revolution = 0;                                // n of row 0
  double first_depth_m = std::numeric_limits<double>::quiet_NaN();  // depth_m[first]
  double last_depth_m = std::numeric_limits<double>::quiet_NaN();   // depth_m[first + R - 1]
  // Row i: (x_(n-1), x_n) with n = first_revolution + i; R rows.
  Eigen::MatrixX2d points_m;
};

// The map centred on the revolution whose depth is nearest `depth` (the first such revolution).
// @param depth_m, x_m  once-per-revolution depth and samples (m), same size, at least R + 1
// @throws InputError on different sizes, a run shorter than R + 1 revolutions, R < 2, or a
//         depth outside [min depth_m, max depth_m]
PoincareMap poincare_map(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                         const Eigen::Ref<const Eigen::VectorXd>& x_m, double depth,
                         const PoincareMapOptions& options = {});

// One map per requested depth, in the order given.
std::vector<PoincareMap> poincare_maps(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                       const std::vector<double>& depths,
                                       const PoincareMapOptions& options = {});

// The map centred on a revolution (constant-depth runs, or a chosen instant).
// @throws InputError as poincare_map, or if centre_revolution is outside the run
PoincareMap poincare_map_at_revolution(const Eigen::Ref<const Eigen::VectorXd>& depth_m,
                                       const Eigen::Ref<const Eigen::VectorXd>& x_m,
                                       Eigen::Index centre_revolution,
                                       const PoincareMapOptions& options = {});

enum class OrbitShape { kFixedPoint, kClusters, kRing, kCloud };

struct OrbitClassOptions {
  // One point (period one) when the detrended spread of the map's samples is at most this
  // times the noise floor: the entry factor of the bifurcation criterion.
  double fixed_point_factor = 2.0;
  // Clusters of period p (2 <= p <= max_cluster_period) when x_n - x_(n-p) (less its mean, which
  // holds the drift) has a robust std (quartile_scale, local_spread.h) of at most
  // max(fixed_point_factor sqrt(2) floor, cluster_tolerance s).
  // A quasi-periodic orbit passes only within |sin(pi nu p)| < 0.1 of a period-p lock.
  int max_cluster_period = 4;
  double cluster_tolerance = 0.2;
  // A ring (the closed curve of a quasi-periodic orbit, an ellipse or a deformed one) when the
  // phase dispersion of OrbitClass is at most this. Measured on 20-point maps with noise at
  // 2.5 % of the amplitude: ellipses 0.045-0.096 (nu = 0.13..0.62), an ellipse deformed by a
  // 30 % second harmonic 0.056-0.063, a random cloud 0.35-0.72. Twenty points of a two-frequency
  // torus span 0.07-0.48 and cannot be told from a ring reliably.
  double ring_phase_dispersion = 0.2;
};

struct OrbitClass {
  OrbitShape shape = OrbitShape::kCloud;
  int period = 0;         // 1 for a fixed point, p for clusters, 0 otherwise
  double spread_m = 0.0;  // detrended spread of the map's R + 1 samples (local_spread.h)
  // Phase dispersion: min over nu of sum (x_(i+1) - x_i)^2 / (2 sum (x - mean)^2) with the
  // samples in order of frac(nu n), cyclic: ~1 for white noise in any order, (2 pi / R)^2-small
  // for a smooth closed curve. NaN when the ring test did not run.
  double phase_dispersion = std::numeric_limits<double>::quiet_NaN();
};

// Tests in order: fixed point, clusters of period 2..max, ring, else cloud.
// @param noise_floor_m  the floor of the bifurcation criterion (BifurcationResult), > 0
// @throws InputError if noise_floor_m <= 0 or the map has fewer than 3 points
OrbitClass classify_orbit(const PoincareMap& map, double noise_floor_m,
                          const OrbitClassOptions& options = {});

const char* to_string(OrbitShape shape);

}  // namespace dynamics
}  // namespace chatterlab
