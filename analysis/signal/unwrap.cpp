#include "analysis/signal/unwrap.h"

#include "analysis/common/constants.h"

namespace chatterlab {
namespace signal {

Eigen::VectorXd unwrap_phase_rad(const Eigen::Ref<const Eigen::VectorXd>& phase_rad) {
  Eigen::VectorXd out = phase_rad;
  double turns = 0.0;
  for (Eigen::Index i = 1; i < phase_rad.size(); ++i) {
    const double jump = phase_rad[i] - phase_rad[i - 1];
    if (jump < -0.5 * kTwoPi) turns += kTwoPi;
    if (jump > 0.5 * kTwoPi) turns -= kTwoPi;
    out[i] = phase_rad[i] + turns;
  }
  return out;
}

}  // namespace signal
}  // namespace chatterlab
