#include "analysis/dynamics/bifurcation_options.h"

#include <cmath>
#include <sstream>

#include "analysis/common/require.h"
#include "analysis/common/summary.h"

namespace chatterlab {
namespace dynamics {

namespace {

template <typename T>
void require(bool rule_holds, const char* field, T value, const char* rule) {
  require_rule(rule_holds, std::string("bifurcation.") + field, value, rule);
}

}  // namespace

void validate(const BifurcationOptions& o) {
  require(o.window_revolutions >= 5 && o.window_revolutions % 2 == 1, "window_revolutions",
          o.window_revolutions, "must be odd and >= 5");
  require(std::isfinite(o.measurement_noise_m) && o.measurement_noise_m >= 0.0,
          "measurement_noise_m", o.measurement_noise_m, "must be >= 0 (0: estimate)");
  require(o.noise_block_revolutions >= 50, "noise_block_revolutions", o.noise_block_revolutions,
          "must be >= 50");
  require(o.noise_quantile >= 0.01 && o.noise_quantile <= 0.5, "noise_quantile", o.noise_quantile,
          "must be in [0.01, 0.5]");
  require(std::isfinite(o.min_noise_floor_m) && o.min_noise_floor_m > 0.0, "min_noise_floor_m",
          o.min_noise_floor_m, "must be > 0");
  require(std::isfinite(o.enter_factor) && o.enter_factor > 0.0, "enter_factor", o.enter_factor,
          "must be > 0");
  require(std::isfinite(o.exit_factor) && o.exit_factor > 0.0 && o.exit_factor <= o.enter_factor,
          "exit_factor", o.exit_factor, "must be in (0, enter_factor]");
  require(o.min_chatter_revolutions >= 1, "min_chatter_revolutions", o.min_chatter_revolutions,
          "must be >= 1");
  require(o.min_stable_revolutions >= 1, "min_stable_revolutions", o.min_stable_revolutions,
          "must be >= 1");
  require(std::isfinite(o.constant_depth_tolerance_m) && o.constant_depth_tolerance_m >= 0.0,
          "constant_depth_tolerance_m", o.constant_depth_tolerance_m, "must be >= 0");
}

}  // namespace dynamics
}  // namespace chatterlab
