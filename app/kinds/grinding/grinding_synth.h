// The `grinding` section of a synth spec (docs/format/synth-spec.md): series of grinding cycles
// simulated by analysis/grinding/grinding_synth.h (002 sec. V) with a true process that differs
// from the lab's nominal model (G1, d_s at the start, R0), missing and late inspections and
// dressings, written as grinding tests (EXPERIMENT_FORMAT section 7) with their truth.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/grinding/grinding_model.h"
#include "analysis/grinding/grinding_synth.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

struct GrindingDressingSynth {
  int before_cycle = 0;
  double depth_mm = 0.0;       // commanded: written to test.yaml
  double true_depth_mm = 0.0;  // what the dresser removed: the truth
};

struct GrindingTestSynth {
  std::string name;  // folder grinding/<name>
  int cycles = 12;
  std::optional<double> G1;           // true G1; default: the nominal model's
  std::optional<double> ds_start;     // true d_s at the start of cycle 1; default: model.ds0_mm
  std::optional<double> R0_start_um;  // default: model.R0_um
  double R0_walk_var_um2 = 4e-9;
  double R0_cycle_var_um2 = 1e-4;
  std::vector<int> uninspected, ds_unmeasured, Ra_unmeasured;
  std::vector<std::pair<int, int>> late;  // {cycle, available_cycle}
  std::vector<GrindingDressingSynth> dressings;
};

struct GrindingSynthSpec : KindSpec {
  double fs_hz = 50;
  grinding::GrindingParameters model;  // the lab's nominal model (test.yaml `model`)
  // Measurement noise (test.yaml `noise`, and the synthesized noise).
  double power_sd_W = 100, Dw_sd_mm = 0.01, ds_sd_mm = 0.001, Ra_sd_um = 0.01,
         roundness_sd_um = 0.1;
  std::array<double, 4> P0{10, 1e-7, 1e-6, 0.01};
  std::array<double, 4> Q{0.04, 4e-11, 4e-9, 1.6e-7};
  // True process noise per fast step on Vw, v, ds; default Q's first three.
  std::optional<std::array<double, 3>> process_var;
  double dress_sd_mm = 0.002;  // test.yaml dress_sd_mm of a test with dressings
  std::vector<grinding::InfeedStage> schedule{{0.0254, 475}, {0.002, 190}, {0.0, 185}};
  std::vector<GrindingTestSynth> tests;
};

GrindingSynthSpec read_grinding_synth(const YAML::Node& n, YamlReader& r);

// Writes grinding/<name>/ tests (fast.csv: cycle, u_mm_s, power in V, Dw in um, calibrated by
// test.yaml; inspections.csv) and each test's truth (per_cycle, a trajectory file
// truth-grinding-<name>.csv at the campaign root, dressings). Returns the number written.
int write_grinding_tests(const GrindingSynthSpec& s, SynthContext& ctx);

}  // namespace chatterlab::app
