#include "analysis/lobes/directional.h"

#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"

namespace chatterlab {
namespace lobes {

Eigen::Matrix2d directional_integral(double Kt, double Kr, double a, double b) {
  const double ss = (b - a) / 2.0 - (std::sin(2.0 * b) - std::sin(2.0 * a)) / 4.0;
  const double cc = (b - a) / 2.0 + (std::sin(2.0 * b) - std::sin(2.0 * a)) / 4.0;
  const double sc = -(std::cos(2.0 * b) - std::cos(2.0 * a)) / 4.0;
  Eigen::Matrix2d h;
  h << -Kt * sc - Kr * ss, -Kt * cc - Kr * sc,  //
      Kt * ss - Kr * sc, Kt * sc - Kr * cc;
  return h;
}

Eigen::Matrix2d engaged_integral(double Kt, double Kr, double theta0, double dtheta, double entry,
                                 double exit) {
  const double two_pi = 2.0 * kPi;
  double a = std::fmod(theta0, two_pi);
  if (a < 0.0) a += two_pi;
  const double b = a + dtheta;
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (const double shift : {0.0, two_pi}) {
    const double lo = std::max(a, entry + shift);
    const double hi = std::min(b, exit + shift);
    if (hi > lo) sum += directional_integral(Kt, Kr, lo, hi);
  }
  return sum;
}

}  // namespace lobes
}  // namespace chatterlab
