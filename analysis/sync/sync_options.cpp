#include "analysis/sync/sync_options.h"

#include <cmath>
#include <sstream>

#include "analysis/common/summary.h"

namespace chatterlab {
namespace sync {

namespace {

template <typename T>
void require(bool rule_holds, const char* prefix, const char* field, T value, const char* rule) {
  if (rule_holds) return;
  std::ostringstream m;
  m << prefix << "." << field << " = " << value << ": " << rule;
  throw InputError(m.str());
}

}  // namespace

void validate(const TachOptions& o) {
  if (o.threshold_V) {
    require(std::isfinite(*o.threshold_V), "tach", "threshold_V", *o.threshold_V, "must be finite");
  }
  require(o.hysteresis_fraction >= 0.0 && o.hysteresis_fraction < 0.5, "tach",
          "hysteresis_fraction", o.hysteresis_fraction, "must be in [0, 0.5)");
  require(o.rpm_tolerance > 0.0 && o.rpm_tolerance < 1.0, "tach", "rpm_tolerance", o.rpm_tolerance,
          "must be in (0, 1)");
}

void validate(const ContourOptions& o) {
  require(o.phase_points == 0 || o.phase_points >= 8, "contour", "phase_points", o.phase_points,
          "must be 0 (samples per revolution) or >= 8");
  require(o.min_air_revolutions >= 2, "contour", "min_air_revolutions", o.min_air_revolutions,
          "must be >= 2");
}

void validate(const OffsetSearchOptions& o) {
  require(o.simulated_revolutions >= 2, "offset", "simulated_revolutions", o.simulated_revolutions,
          "must be >= 2");
  require(o.coarse_step_deg > 0.0 && o.coarse_step_deg <= 10.0, "offset", "coarse_step_deg",
          o.coarse_step_deg, "must be in (0, 10]");
  require(o.resolution_deg > 0.0 && o.resolution_deg <= o.coarse_step_deg, "offset",
          "resolution_deg", o.resolution_deg, "must be in (0, coarse_step_deg]");
  require(o.ambiguity_ratio >= 0.0 && std::isfinite(o.ambiguity_ratio), "offset", "ambiguity_ratio",
          o.ambiguity_ratio, "must be finite and >= 0");
  require(o.settle_tolerance > 0.0 && std::isfinite(o.settle_tolerance), "offset",
          "settle_tolerance", o.settle_tolerance, "must be finite and > 0");
}

}  // namespace sync
}  // namespace chatterlab
