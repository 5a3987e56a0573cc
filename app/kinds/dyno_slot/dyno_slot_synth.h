// The `dyno` section of a synth spec (docs/format/synth-spec.md): dyno-slot tests, one per feed,
// with forces of given cutting coefficients (analysis/cutting/slot_synth.h), a dynamometer at an
// angle to the feed, offsets and noise, written in volts.
#pragma once

#include <yaml-cpp/yaml.h>

#include <utility>
#include <vector>

#include "analysis/common/cutting_coefficients.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

struct DynoSynthSpec : KindSpec {
  double rpm = 0, depth_m = 0, fs = 0, duration_s = 0, theta_dyn_deg = 0, noise_N = 0;
  double sensitivity = 1.0;
  std::pair<double, double> offsets{0, 0};
  std::vector<double> feeds_m;
  CuttingCoefficients k;
};

DynoSynthSpec read_dyno_synth(const YAML::Node& n, YamlReader& r);

// Writes dyno/f<feed in um>/ tests, one per feed; adds the coefficients and the dynamometer
// angle to truth (entry `dyno/`, matched by the group of the dyno/ tests). Returns the number
// of tests written.
int write_dyno_tests(const DynoSynthSpec& d, SynthContext& ctx);

}  // namespace chatterlab::app
