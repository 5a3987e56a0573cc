// The `tap` section of a synth spec (docs/format/synth-spec.md): hammer hits on x and y with the
// exact response of given modes, noise, and optionally a double hit.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "analysis/frf/mode.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

struct TapAxisSynth {
  std::vector<frf::Mode> modes;
  int double_hit = 0;  // 1-based index of a hit that bounces; 0: none
};

struct TapSynthSpec : KindSpec {
  double fs_hz = 25600;
  int hits = 5;
  double hit_spacing_s = 1.0;
  std::string response = "acceleration";
  double noise_pct = 1.0;
  double force_peak_N = 150;
  double pulse_width_s = 3e-4;
  std::map<std::string, TapAxisSynth> axes;  // "x", "y"
};

TapSynthSpec read_tap_synth(const YAML::Node& n, YamlReader& r);

// Writes tap/<axis>/ tests; adds the modes to truth (each test's modes, and the campaign-wide
// `modal` from the first mode of x). Returns the number of tests written.
int write_tap_tests(const TapSynthSpec& s, SynthContext& ctx);

}  // namespace chatterlab::app
