#include "analysis/milling/engagement.h"

#include <cmath>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace milling {

namespace {}

EngagementWindow engagement_window(Operation op, double radius_m, double radial_immersion_m) {
  if (!(radius_m > 0.0) || !std::isfinite(radius_m)) {
    std::ostringstream m;
    m << "engagement_window: radius_m = " << radius_m << ": must be finite and > 0";
    throw InputError(m.str());
  }
  if (!(radial_immersion_m > 0.0) || !(radial_immersion_m <= 2.0 * radius_m)) {
    std::ostringstream m;
    m << "engagement_window: radial_immersion_m = " << radial_immersion_m
      << ": must satisfy 0 < r_i <= 2 r = " << 2.0 * radius_m;
    throw InputError(m.str());
  }
  // 000 eq. 2.9: the tip reaches the original surface r cos(theta) = r - r_i.
  const double swept = std::acos(1.0 - radial_immersion_m / radius_m);
  if (op == Operation::kUpMilling) return {0.0, swept};
  // Down-milling: r cos(theta) = -(r - r_i) on the way in, the finished wall at theta = pi.
  return {kPi - swept, kPi};
}

}  // namespace milling
}  // namespace chatterlab
