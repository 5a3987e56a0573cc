// Small order statistics shared by the analysis steps.
#pragma once

#include <Eigen/Core>

namespace chatterlab {

// The median of v (the mean of the two middle values for an even count), by nth_element on the
// copy it takes. v must not be empty.
double median(Eigen::VectorXd v);

}  // namespace chatterlab
