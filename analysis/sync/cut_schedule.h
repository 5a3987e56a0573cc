// When the tool is in the workpiece and at which axial depth (test.yaml cut_window_s and
// axial_depth_mm, EXPERIMENT_FORMAT.md kind: cut), and the same schedule as a simulator depth
// profile.
#pragma once

#include <limits>

#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace sync {

// Linear from depth_start_m at cut_start_s to depth_end_m at cut_end_s (record time, s; m).
struct CutSchedule {
  double cut_start_s = std::numeric_limits<double>::quiet_NaN();
  double cut_end_s = std::numeric_limits<double>::quiet_NaN();
  double depth_start_m = std::numeric_limits<double>::quiet_NaN();
  double depth_end_m = std::numeric_limits<double>::quiet_NaN();  // == start: constant depth

  double depth_at_m(double t_s) const;  // clamped to the cut window
  bool ramped() const { return depth_end_m != depth_start_m; }
};

// The ramp of a ramped cut as the simulator runs it (000 sec. 5.2): from depth_start_m to
// depth_end_m over the cut window's revolutions at the nominal speed,
//   revolutions_per_mm = (cut_end_s - cut_start_s) spindle_rpm / 60 / |depth_end - depth_start|.
// @throws InputError unless the cut is ramped, its window increasing and spindle_rpm > 0
milling::DepthProfile ramp_depth_profile(const CutSchedule& cut, double spindle_rpm);

}  // namespace sync
}  // namespace chatterlab
