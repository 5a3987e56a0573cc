#include "analysis/cutting/dyno_options.h"

#include <cmath>
#include <sstream>
#include <string>

#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace cutting {

namespace {

template <typename T>
void require(bool rule_holds, const char* field, T value, const char* rule) {
  require_rule(rule_holds, std::string("dyno.") + field, value, rule);
}

}  // namespace

void validate(const DynoOptions& o) {
  require(std::isfinite(o.zero_threshold_V), "zero_threshold_V", o.zero_threshold_V,
          "must be finite");
  require(std::isfinite(o.zero_hysteresis_V) && o.zero_hysteresis_V >= 0.0, "zero_hysteresis_V",
          o.zero_hysteresis_V, "must be >= 0");
  require(o.rpm_tolerance > 0.0 && o.rpm_tolerance < 1.0, "rpm_tolerance", o.rpm_tolerance,
          "must be in (0, 1)");
  require(o.min_revolutions >= 1, "min_revolutions", o.min_revolutions, "must be >= 1");
  require(o.min_samples_per_revolution >= 4.0, "min_samples_per_revolution",
          o.min_samples_per_revolution, "must be >= 4");
  require(o.theta_coarse_step_deg > 0.0 && o.theta_coarse_step_deg <= 45.0, "theta_coarse_step_deg",
          o.theta_coarse_step_deg, "must be in (0, 45]");
  require(o.theta_resolution_deg > 0.0 && o.theta_resolution_deg <= o.theta_coarse_step_deg,
          "theta_resolution_deg", o.theta_resolution_deg, "must be in (0, theta_coarse_step_deg]");
  require(o.switching_contrast_warning >= 0.0 && o.switching_contrast_warning <= 1.0,
          "switching_contrast_warning", o.switching_contrast_warning, "must be in [0, 1]");
  require(o.mean_force_model == SlotMeanForceModel::kSingleToothChip ||
              o.mean_force_model == SlotMeanForceModel::kDissertationEq3_5,
          "mean_force_model", static_cast<int>(o.mean_force_model), "unknown model");
  require(o.fit_r_squared_warning <= 1.0, "fit_r_squared_warning", o.fit_r_squared_warning,
          "must be <= 1");
}

}  // namespace cutting
}  // namespace chatterlab
