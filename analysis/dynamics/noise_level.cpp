#include "analysis/dynamics/noise_level.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace dynamics {

double white_noise_sigma(const Eigen::Ref<const Eigen::VectorXd>& signal) {
  const Eigen::Index n = signal.size();
  if (n < 3) {
    std::ostringstream m;
    m << "noise level: signal has " << n << " samples: at least 3 needed";
    throw InputError(m.str());
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(signal[i])) {
      std::ostringstream m;
      m << "noise level: sample " << i << " = " << signal[i] << ": must be finite";
      throw InputError(m.str());
    }
  }
  std::vector<double> d(static_cast<std::size_t>(n - 2));
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    d[static_cast<std::size_t>(i - 1)] = std::abs(signal[i + 1] - 2.0 * signal[i] + signal[i - 1]);
  }
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return 1.482602218505602 * *mid / std::sqrt(6.0);
}

}  // namespace dynamics
}  // namespace chatterlab
