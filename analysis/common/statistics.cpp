#include "analysis/common/statistics.h"

#include <algorithm>
#include <cstddef>

namespace chatterlab {

double median(Eigen::VectorXd v) {
  const auto n = static_cast<std::size_t>(v.size());
  double* mid = v.data() + n / 2;
  std::nth_element(v.data(), mid, v.data() + n);
  if (n % 2 == 1) return *mid;
  const double upper = *mid;
  const double lower = *std::max_element(v.data(), mid);
  return 0.5 * (lower + upper);
}

}  // namespace chatterlab
