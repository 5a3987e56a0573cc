#include "analysis/dynamics/revolution_sampling.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace dynamics {

namespace {}  // namespace

RevolutionCrossings revolution_crossings(const Eigen::Ref<const Eigen::VectorXd>& theta_rad,
                                         double theta_s_rad) {
  if (!std::isfinite(theta_s_rad)) {
    std::ostringstream m;
    m << "theta_s = " << theta_s_rad << " rad: must be finite";
    throw InputError(m.str());
  }
  const Eigen::Index n = theta_rad.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(theta_rad[i])) {
      std::ostringstream m;
      m << "theta[" << i << "] = " << theta_rad[i] << " rad: must be finite";
      throw InputError(m.str());
    }
    if (i > 0 && !(theta_rad[i] > theta_rad[i - 1])) {
      std::ostringstream m;
      m << "theta[" << i << "] = " << theta_rad[i] << " rad: must be above theta[" << i - 1
        << "] = " << theta_rad[i - 1] << " (unwrapped, strictly increasing)";
      throw InputError(m.str());
    }
  }

  RevolutionCrossings out;
  out.sample_count = n;
  if (n == 0) return out;

  std::vector<double> position;
  std::vector<int> revolution;
  long long k = static_cast<long long>(std::ceil((theta_rad[0] - theta_s_rad) / kTwoPi));
  // The division rounds: step k so that the first target is the first one at or above theta(0).
  while (theta_s_rad + kTwoPi * static_cast<double>(k - 1) >= theta_rad[0]) --k;
  while (theta_s_rad + kTwoPi * static_cast<double>(k) < theta_rad[0]) ++k;

  Eigen::Index i = 0;
  for (double target = theta_s_rad + kTwoPi * static_cast<double>(k); target <= theta_rad[n - 1];
       target = theta_s_rad + kTwoPi * static_cast<double>(++k)) {
    while (i + 1 < n && theta_rad[i + 1] <= target) ++i;  // theta(i) <= target < theta(i+1)
    const double p = i + 1 < n ? static_cast<double>(i) +
                                     (target - theta_rad[i]) / (theta_rad[i + 1] - theta_rad[i])
                               : static_cast<double>(i);
    position.push_back(p);
    revolution.push_back(static_cast<int>(k));
  }
  out.sample_position = Eigen::Map<const Eigen::VectorXd>(
      position.data(), static_cast<Eigen::Index>(position.size()));
  out.revolution = Eigen::Map<const Eigen::VectorXi>(revolution.data(),
                                                     static_cast<Eigen::Index>(revolution.size()));
  return out;
}

Eigen::VectorXd sample_at_crossings(const RevolutionCrossings& crossings,
                                    const Eigen::Ref<const Eigen::VectorXd>& signal) {
  if (signal.size() != crossings.sample_count) {
    std::ostringstream m;
    m << "once-per-revolution sampling: signal has " << signal.size()
      << " samples, the angle record " << crossings.sample_count << ": must be equal";
    throw InputError(m.str());
  }
  const Eigen::Index last = signal.size() - 1;
  Eigen::VectorXd x(crossings.size());
  for (Eigen::Index c = 0; c < crossings.size(); ++c) {
    const double p = crossings.sample_position[c];
    const auto i = static_cast<Eigen::Index>(std::floor(p));
    if (i >= last) {
      x[c] = signal[last];
      continue;
    }
    const double f = p - static_cast<double>(i);
    x[c] = (1.0 - f) * signal[i] + f * signal[i + 1];
  }
  return x;
}

}  // namespace dynamics
}  // namespace chatterlab
