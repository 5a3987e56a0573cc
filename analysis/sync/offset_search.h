// Offset-angle search between one simulated and one measured revolution (000 sec. 5.1):
// "minimizing the error between the simulated and experimental tool trajectories for one
// revolution by testing every possible phase angle at one-degree increments", then refined.
//
// The measured revolution is given on the tach-phase grid phi_j = 2 pi j / N (revolution_mean.h),
// the simulated one on theta_1 = 2 pi a / S (the simulator's step grid). A candidate offset
// delta puts measured point j at theta_1 = phi_j + delta, so its error is
//   E(delta) = sqrt( 1/(2N) sum_j [ (xm_j - xs(phi_j + delta))^2 + (ym_j - ys(phi_j + delta))^2 ]
//   ),
// the RMS over the revolution of both axes, xs, ys linearly interpolated (periodic) on the
// simulated grid. The simulated revolution is never re-run: every candidate is a resampling.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "analysis/sync/sync_options.h"

namespace chatterlab {
namespace sync {

// E(delta) of one measured/simulated pair (see above).
class RevolutionMatcher {
 public:
  // @param measured_x_m, measured_y_m  on phi_j = 2 pi j / N, N >= 8, same size, finite
  // @param simulated_x_m, simulated_y_m  on theta_1 = 2 pi a / S, S >= 8, same size, finite
  // @throws InputError naming the argument that breaks its rule
  RevolutionMatcher(const Eigen::Ref<const Eigen::VectorXd>& measured_x_m,
                    const Eigen::Ref<const Eigen::VectorXd>& measured_y_m,
                    const Eigen::Ref<const Eigen::VectorXd>& simulated_x_m,
                    const Eigen::Ref<const Eigen::VectorXd>& simulated_y_m);

  // E(delta), m; delta in rad, any real value.
  double rms_error_m(double offset_rad) const;

  // RMS over the revolution of both measured axes, m (the scale of E).
  double measured_rms_m() const;

  const Eigen::VectorXd& measured_x_m() const { return mx_; }
  const Eigen::VectorXd& measured_y_m() const { return my_; }
  const Eigen::VectorXd& simulated_x_m() const { return sx_; }
  const Eigen::VectorXd& simulated_y_m() const { return sy_; }

 private:
  Eigen::VectorXd mx_, my_, sx_, sy_;
};

struct OffsetSearch {
  double offset_angle_deg = std::numeric_limits<double>::quiet_NaN();  // in [0, 360)
  double rms_error_m = std::numeric_limits<double>::quiet_NaN();       // E at the offset
  Eigen::VectorXd candidate_deg;  // coarse candidates k * coarse_step_deg in [0, 360)
  Eigen::VectorXd error_m;        // E at each candidate (the error curve)
  // The other teeth's alignment: the minimum of the error curve within +-90 / n deg of
  // offset + k 360 / n (k = 1..n-1; the best k), refined. With two teeth, "the other half
  // turn". NaN with one tooth.
  double runner_up_deg = std::numeric_limits<double>::quiet_NaN();
  double runner_up_error_m = std::numeric_limits<double>::quiet_NaN();
  double runner_up_ratio = std::numeric_limits<double>::quiet_NaN();  // runner-up E / best E
  // runner_up_ratio <= 1 + options.ambiguity_ratio: the offset is determined modulo 360 / n
  // only.
  bool ambiguous = false;
};

// Coarse grid over [0, 360) in options.coarse_step_deg, golden-section refinement of the best
// point on +-1 coarse step to options.resolution_deg, runner-up likewise.
// @param teeth  n >= 1 (where the runner-up is looked for)
// @throws InputError for teeth < 1 or options that break their rules
OffsetSearch search_offset(const RevolutionMatcher& matcher, int teeth,
                           const OffsetSearchOptions& options = {});

}  // namespace sync
}  // namespace chatterlab
