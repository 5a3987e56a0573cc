#include "analysis/lobes/lobes.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "analysis/common/constants.h"
#include "analysis/common/require.h"
#include "analysis/milling/engagement.h"

namespace chatterlab {
namespace lobes {

const char* to_string(BoundaryType t) {
  switch (t) {
    case BoundaryType::kFlip:
      return "flip";
    case BoundaryType::kHopf:
      return "hopf";
    case BoundaryType::kFold:
      return "fold";
  }
  return "?";
}

namespace {

void validate_modes(const std::vector<ModalParameters>& modes, const std::string& field) {
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string f = field + "[" + std::to_string(i) + "]";
    const ModalParameters& p = modes[i];
    require_rule(std::isfinite(p.m_kg) && p.m_kg > 0.0, f + ".m_kg", p.m_kg,
                 "must be finite and > 0");
    require_rule(std::isfinite(p.c_kg_s) && p.c_kg_s >= 0.0, f + ".c_kg_s", p.c_kg_s,
                 "must be finite and >= 0");
    require_rule(std::isfinite(p.k_N_m) && p.k_N_m > 0.0, f + ".k_N_m", p.k_N_m,
                 "must be finite and > 0");
  }
}

}  // namespace

void validate(const LobesInput& in) {
  require_rule(in.teeth >= 1 && in.teeth <= milling::kMaxTeeth, "lobes.teeth", in.teeth,
               "must be 1.." + std::to_string(milling::kMaxTeeth));
  require_rule(std::isfinite(in.radius_m) && in.radius_m > 0.0, "lobes.radius_m", in.radius_m,
               "must be finite and > 0");
  const auto n = static_cast<std::size_t>(in.teeth);
  require_rule(in.Kt_N_m2.size() == n, "lobes.Kt_N_m2.size", in.Kt_N_m2.size(), "must equal teeth");
  require_rule(in.Kr_N_m2.size() == n, "lobes.Kr_N_m2.size", in.Kr_N_m2.size(), "must equal teeth");
  for (std::size_t p = 0; p < n; ++p) {
    require_rule(std::isfinite(in.Kt_N_m2[p]) && in.Kt_N_m2[p] >= 0.0,
                 "lobes.Kt_N_m2[" + std::to_string(p) + "]", in.Kt_N_m2[p],
                 "must be finite and >= 0");
    require_rule(std::isfinite(in.Kr_N_m2[p]) && in.Kr_N_m2[p] >= 0.0,
                 "lobes.Kr_N_m2[" + std::to_string(p) + "]", in.Kr_N_m2[p],
                 "must be finite and >= 0");
  }
  require_rule(std::isfinite(in.radial_immersion_m) && in.radial_immersion_m > 0.0 &&
                   in.radial_immersion_m <= 2.0 * in.radius_m,
               "lobes.radial_immersion_m", in.radial_immersion_m, "must be > 0 and <= 2 radius_m");
  validate_modes(in.x_modes, "lobes.x_modes");
  validate_modes(in.y_modes, "lobes.y_modes");
  require_rule(!in.x_modes.empty() || !in.y_modes.empty(), "lobes.x_modes.size", in.x_modes.size(),
               "x_modes and y_modes must not both be empty");
  require_rule(!in.spindle_rpm.empty(), "lobes.spindle_rpm.size", in.spindle_rpm.size(),
               "must be >= 1");
  for (std::size_t i = 0; i < in.spindle_rpm.size(); ++i) {
    require_rule(std::isfinite(in.spindle_rpm[i]) && in.spindle_rpm[i] > 0.0,
                 "lobes.spindle_rpm[" + std::to_string(i) + "]", in.spindle_rpm[i],
                 "must be finite and > 0");
  }
  require_rule(std::isfinite(in.max_depth_m) && in.max_depth_m > 0.0, "lobes.max_depth_m",
               in.max_depth_m, "must be finite and > 0");
}

int automatic_steps_per_tooth(const LobesInput& in) {
  const milling::EngagementWindow w =
      milling::engagement_window(in.operation, in.radius_m, in.radial_immersion_m);
  const double tooth_angle = 2.0 * kPi / in.teeth;
  const double engaged = std::max(w.exit_rad - w.entry_rad, 1e-9);
  const double m = std::ceil(kEngagedIntervals * tooth_angle / engaged);
  return static_cast<int>(std::clamp(m, 30.0, static_cast<double>(kMaxAutoStepsPerTooth)));
}

}  // namespace lobes
}  // namespace chatterlab
