#include "analysis/signal/pulses.h"

#include <cmath>
#include <sstream>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace signal {

std::vector<double> rising_edges(const Eigen::Ref<const Eigen::VectorXd>& x, double threshold,
                                 double hysteresis) {
  if (!std::isfinite(threshold)) {
    std::ostringstream m;
    m << "rising_edges.threshold = " << threshold << ": must be finite";
    throw InputError(m.str());
  }
  if (!std::isfinite(hysteresis) || hysteresis < 0.0) {
    std::ostringstream m;
    m << "rising_edges.hysteresis = " << hysteresis << ": must be finite and >= 0";
    throw InputError(m.str());
  }
  const double arm_level = threshold - hysteresis;
  std::vector<double> edges;
  bool armed = false;
  Eigen::Index last = -1;  // last finite sample, the left end of the interpolation
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double v = x[i];
    if (std::isnan(v)) continue;
    if (armed && v >= threshold) {
      // Armed implies every finite sample since arming was below threshold: x[last] < v.
      const double prev = x[last];
      const double frac = (threshold - prev) / (v - prev);
      edges.push_back(static_cast<double>(last) + frac * static_cast<double>(i - last));
      armed = false;
    } else if (v < arm_level) {
      armed = true;
    }
    last = i;
  }
  return edges;
}

}  // namespace signal
}  // namespace chatterlab
