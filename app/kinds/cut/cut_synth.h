// The `cut` section of a synth spec (docs/format/synth-spec.md): a milling run simulated with known
// modal parameters and per-tooth coefficients (analysis/milling), seen through capacitive sensors
// (sensor_to_tip, volts with scale and gap offset, runout and out-of-roundness contour,
// measurement noise) with a laser tachometer whose rising edge falls where theta_1 equals the
// offset angle (EXPERIMENT_FORMAT.md, kind: cut).
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/modal_parameters.h"
#include "app/core/campaign.h"
#include "app/core/yaml_reader.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

struct CutTestSynth {
  std::string name;  // folder cuts/<name>
  double depth_start_m = 0, depth_end_m = 0;
  std::optional<double> revolutions_per_mm;  // ramp rate when the depth changes
  std::optional<double> duration_s;          // cutting time at constant depth
  // theta_1 at the tachometer edge, deg; unset: drawn uniformly in [0, 360) from the spec's
  // seed (written to truth.yaml), so that a test can use an offset it did not choose.
  std::optional<double> offset_angle_deg;
};

struct CutSynthSpec : KindSpec {
  double fs_hz = 100000;
  double spindle_rpm = 15000;
  double feed_per_tooth_m = 0.0635e-3;
  double radial_immersion_m = 0.382e-3;
  std::string operation = "up-milling";
  ModalParameters modal;                 // same on x and y
  std::vector<double> Kt_N_m2, Kr_N_m2;  // per tooth
  double sensor_to_tip = 2.78;           // 000 sec. 3.1
  double scale_m_per_V = 3.9e-5;         // sensor calibration: metres at the sensor per volt
  double gap_offset_m = -1.95e-4;        // test.yaml channel offset: sensor at 5 V when centred
  double noise_m = 5e-7;                 // at the tip (000 sec. 6.1)
  double runout_m = 3e-6;                // eccentricity seen at the sensor
  double runout_angle_deg = 40;
  std::vector<double> out_of_round_m{8e-7, 3e-7};  // harmonics 2, 3 of the tool contour
  int air_revolutions = 50;                        // spinning before the cut: the air window
  std::vector<CutTestSynth> tests;
};

// Also checks the section against the spec's tool (one coefficient per tooth) when it has one.
CutSynthSpec read_cut_synth(const YAML::Node& n, const SynthContext& ctx, YamlReader& r);

// Writes cuts/<name>/ tests (signals.f32 with channels x, y, tach); adds the modal parameters
// and per-tooth coefficients to truth (top-level `modal`, `coefficients`) and each test's offset
// angle.
// Needs ctx.tool (the parser reports a spec without one).
int write_cut_tests(const CutSynthSpec& s, SynthContext& ctx);

}  // namespace chatterlab::app
