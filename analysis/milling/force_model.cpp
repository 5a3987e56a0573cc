#include "analysis/milling/force_model.h"

#include <cmath>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace milling {

namespace {}

double tooth_angle_rad(double theta1_rad, int p, int n) {
  if (n < 1 || p < 1 || p > n) {
    std::ostringstream m;
    m << "tooth_angle_rad: p = " << p << ", n = " << n << ": must satisfy 1 <= p <= n";
    throw InputError(m.str());
  }
  return theta1_rad + static_cast<double>(p - 1) * kTwoPi / static_cast<double>(n);
}

Eigen::Vector2d tooth_tip_position_m(double radius_m, double theta_rad) {
  return {radius_m * std::sin(theta_rad), radius_m * std::cos(theta_rad)};
}

double static_chip_thickness_m(double feed_per_tooth_m, double theta_rad) {
  return feed_per_tooth_m * std::sin(theta_rad);
}

bool in_cut(double theta_rad, double entry_rad, double exit_rad) {
  double t = std::fmod(theta_rad, kTwoPi);
  if (t < 0.0) t += kTwoPi;
  return t >= entry_rad && t < exit_rad;
}

ToothForce tooth_force(const CuttingCoefficients& k, double chip_thickness_m, double depth_m,
                       bool engaged) {
  ToothForce f;
  if (!engaged || !(chip_thickness_m > 0.0)) return f;
  f.tangential_N = k.Kt_N_m2 * depth_m * chip_thickness_m + k.Kte_N_m * depth_m;
  f.radial_N = k.Kr_N_m2 * depth_m * chip_thickness_m + k.Kre_N_m * depth_m;
  return f;
}

Eigen::Vector2d tooth_force_xy_N(const ToothForce& f, double theta_rad) {
  const double c = std::cos(theta_rad);
  const double s = std::sin(theta_rad);
  return {-(f.tangential_N * c + f.radial_N * s), f.tangential_N * s - f.radial_N * c};
}

}  // namespace milling
}  // namespace chatterlab
