// Eigen vectors as std::vector, for the figure series and the json arrays of the kinds.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace chatterlab::app {

// A copy of v's values.
inline std::vector<double> to_vector(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

}  // namespace chatterlab::app
