// Engagement (entry/exit) angles of the traditional chip model, 000 eqs 2.8-2.9 for up-milling
// and their down-milling counterpart (derived in docs/simulator.md).
//
// Same conventions as force_model.h: theta from +y towards +x, tip at (r sin, r cos), the tool
// turning with increasing theta (clockwise in the x-y plane), feed along +x.
//   Up-milling, workpiece on +y (000 eqs 2.8-2.9): entry 0 on the finished wall y = r, exit
//     acos(1 - r_i / r) on the original surface y = r - r_i; chip h sin(theta) grows from 0.
//   Down-milling, workpiece on -y (the tip then moves with the feed, -x tip velocity against a
//     workpiece moving -x relative to the tool): entry pi - acos(1 - r_i / r) on the original
//     surface y = -(r - r_i), exit pi on the finished wall y = -r; chip h sin(theta) falls to 0.
#pragma once

#include "analysis/milling/simulation_options.h"

namespace chatterlab {
namespace milling {

struct EngagementWindow {
  double entry_rad = 0.0;  // first engaged angle
  double exit_rad = 0.0;   // last engaged angle; 0 <= entry <= exit <= pi
};

// Throws InputError unless radius_m > 0 and 0 < radial_immersion_m <= 2 radius_m.
EngagementWindow engagement_window(Operation op, double radius_m, double radial_immersion_m);

// +1 for up-milling (workpiece and original surface on +y), -1 for down-milling (on -y).
inline double workpiece_side(Operation op) { return op == Operation::kUpMilling ? 1.0 : -1.0; }

}  // namespace milling
}  // namespace chatterlab
