// What `chatterlab lobes` and the campaign report's lobes section share: a method's results as
// the JSON of EXPERIMENT_FORMAT.md "Stability lobe specs", and the lobes figure with measured
// points overlaid (docs/lobes.md).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "analysis/lobes/lobes.h"
#include "render/figure.h"

namespace chatterlab::app {

// The format's boundary type: "hopf" for a complex critical multiplier, "flip" for a real one
// (either sign: over a revolution of unequal teeth the tooth-pass flip crosses at +1; the
// library's kFold, docs/lobes.md "Boundary type").
const char* format_boundary_type(lobes::BoundaryType t);

// {"spindle_rpm", "limit_depth_mm" (null: stable up to the largest depth), "type" (with_type),
// "chatter_hz", "runtime_s", "minimum_limit_depth_mm", "minimum_at_rpm" (null when stable at
// every speed)} plus, for semi-discretization, "period" and the critical multipliers.
nlohmann::json lobes_method_json(const lobes::LobesResult& r, bool semi_discretization);

// The lowest limit over the speeds and its speed; nullopt when stable at every speed.
struct LobeMinimum {
  double depth_m = 0.0;
  double spindle_rpm = 0.0;
};
std::optional<LobeMinimum> lobe_minimum(const lobes::LobesResult& r);

// A cut measured in a campaign, drawn over the lobes (docs/lobes.md "Measured points"): a
// constant-depth cut is a point, stable or chatter by its Poincare class; a ramp is a vertical
// segment over its depths, stable below its measured bifurcation depth and chatter above.
struct MeasuredPoint {
  std::string test;  // test id, e.g. "cuts/incline-1"
  double spindle_rpm = 0.0;
  bool ramp = false;
  double depth_low_m = 0.0, depth_high_m = 0.0;  // equal for a constant-depth cut
  std::optional<bool> chatter;  // constant depth: the measured state (nullopt: not determined)
  // Ramps: the depth ranges measured stable and in chatter (empty when not determined), and the
  // bifurcation depth between them.
  std::vector<std::pair<double, double>> stable_m, chatter_m;
  std::optional<double> bifurcation_depth_m;
};

// An incline and a decline at one speed (000 table 5.1): chatter begins at `onset_m` going up
// and ends at `end_m` going down.
struct Hysteresis {
  double spindle_rpm = 0.0;
  std::string incline, decline;  // test ids
  double onset_m = 0.0, end_m = 0.0;
};

// One limit curve of the figure.
struct LobeCurve {
  std::string label;  // legend, e.g. "semi-discretization"
  const lobes::LobesResult* result = nullptr;
  bool dashed = false;
  bool frequencies = false;  // also in the chatter-frequency panel
  bool typed = false;        // its frequencies split by boundary type (flip/Hopf)
};

// Two panels: limit depth against spindle speed (each curve, then the measured points) and
// the chatter frequency at the boundary of the curves that ask for it.
render::Figure lobes_figure(const std::vector<LobeCurve>& curves,
                            const std::vector<MeasuredPoint>& measured,
                            const std::vector<Hysteresis>& hysteresis, double max_depth_m);

}  // namespace chatterlab::app
