// The `sifs` section of a synth spec (docs/format/synth-spec.md): a spindle-integrated force
// sensor campaign (EXPERIMENT_FORMAT.md section 6) made by analysis/sifs/sifs_synth.h from a
// known calibration matrix and tip-to-sensor plant: static tests <folder>/static-{x,y,z}, tap
// tests <folder>/tap-{x,y} and cut tests <folder>/cut-n<rpm, 5 digits>, with their truth
// (format section 6 "truth.yaml (synthetic sifs campaigns)").
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "analysis/sifs/sensor_model.h"
#include "analysis/sifs/sifs_synth.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

struct SifsSynthSpec : KindSpec {
  std::string folder = "sifs";  // tests <folder>/static-x, ...
  Eigen::Matrix3d C = sifs::default_calibration_matrix();
  std::vector<sifs::SensorMode> plant_x = sifs::default_plant_x();
  std::vector<sifs::SensorMode> plant_y = sifs::default_plant_y();
  double washer_scale_N_per_V = 200;  // washer channels written in volts (003: 200 N/V)
  double filter_rate_hz = 10000;      // sifs-cut filter_rate_hz; the truth's harmonic limit
  // static (EXPERIMENT_FORMAT sifs-static)
  sifs::StaticSynthOptions stat;
  std::array<double, 3> load_sign{1.0, 1.0, -1.0};  // x, y pulled along +, z weights hang (-z)
  // taps (sifs-tap)
  sifs::TapSynthOptions tap;
  double hammer_scale_N_per_V = 444.8;  // 003: Dytran 5800B4, 2.248 mV/N
  std::array<double, 2> tap_band_hz{100, 4000};
  int tap_modes = 3;  // test.yaml `modes`
  // cuts (sifs-cut); tool teeth and radius from the spec's `tool`
  std::vector<double> rpm{4500, 9000, 11600};
  sifs::CutSynthOptions cut;
  double axial_depth_mm = 2.0;
  double radial_immersion_mm = -1;  // < 0: the tool radius (half immersion)
  double feed_per_tooth_mm = 0.05;
  double dyno_scale_N_per_V = 500;
  std::array<double, 2> cut_band_hz{10, 4000};
  int unbalance_harmonics = 2;
};

// Reads the section (every problem keyed `sifs.<key>`); cut tests need ctx.tool.
std::shared_ptr<const KindSpec> parse_sifs_synth(const YAML::Node& section, const SynthContext& ctx,
                                                 YamlReader& r);

// Writes the tests (raw .f32 signals, test.yaml), the truth force files
// truth/<folder with '/' as '-'>-cut-n<rpm>.csv, and truth.yaml's calibration_matrix,
// sensitivity_matrix and one entry per tap and cut test (and each static test's drift).
// Returns the number of tests written.
int write_sifs_synth(const KindSpec& spec, SynthContext& ctx);

}  // namespace chatterlab::app
