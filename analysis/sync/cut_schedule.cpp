#include "analysis/sync/cut_schedule.h"

#include <algorithm>
#include <cmath>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"

namespace chatterlab {
namespace sync {

double CutSchedule::depth_at_m(double t_s) const {
  if (depth_end_m == depth_start_m) return depth_start_m;
  const double u = std::clamp((t_s - cut_start_s) / (cut_end_s - cut_start_s), 0.0, 1.0);
  return depth_start_m + u * (depth_end_m - depth_start_m);
}

milling::DepthProfile ramp_depth_profile(const CutSchedule& cut, double spindle_rpm) {
  require_rule(std::isfinite(cut.depth_start_m) && std::isfinite(cut.depth_end_m) && cut.ramped(),
               "cut.axial_depth_m", cut.depth_end_m, "must differ from the start depth (a ramp)");
  require_rule(cut.cut_end_s > cut.cut_start_s, "cut.cut_end_s", cut.cut_end_s,
               "must be after cut_start_s");
  require_rule(spindle_rpm > 0 && std::isfinite(spindle_rpm), "cut.spindle_rpm", spindle_rpm,
               "must be finite and > 0");
  const double revolutions = (cut.cut_end_s - cut.cut_start_s) * spindle_rpm / kSecondsPerMinute;
  return milling::DepthProfile::ramp(
      cut.depth_start_m, cut.depth_end_m,
      revolutions / (std::abs(cut.depth_end_m - cut.depth_start_m) * kMToMm));
}

}  // namespace sync
}  // namespace chatterlab
