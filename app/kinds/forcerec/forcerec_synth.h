// The synth section `forcerec` (docs/format/synth-spec.md), shared by its two writers:
// forcerec_synth.cpp (dyno-frf hammer tests of 004 Table 3.1's axes, and the first-pass
// `hammer-before` tests of the optional `cuts.drift`) and forcerec_cut_synth.cpp (the
// force-record cut tests of the optional `cuts:` block with their truth, format section 4).
//
// Both writers simulate the continuous dynamometer model: the force is evaluated at
// kOversampling times the record's rate (each fine step holding it at its mid-point) and the
// true model is discretized there (zero-order hold over 1/16 of a sample), then sampled at the
// record's rate, so that no method sees the discretization it would invert (no inverse crime,
// notes/004.md sec. 9 item 4).
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "analysis/common/cutting_coefficients.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/table31.h"
#include "analysis/forcerec/transfer_fit.h"
#include "analysis/milling/simulation_options.h"
#include "app/core/yaml_reader.h"
#include "app/pipeline/kind.h"
#include "app/synth/synth.h"

namespace chatterlab::app::forcerec_synth {

using forcerec::kTable31;
using forcerec::Table31Axis;

// Fine steps per record sample of the forward simulation.
inline constexpr int kOversampling = 16;

// The Table 3.1 row of axis 'x', 'y' or 'z' (a broken invariant otherwise).
const Table31Axis& table31_axis(char axis);
// The true model of that axis (transfer_model_from_coefficients of its row).
forcerec::TransferModel table31_model(char axis);
// G(s / scale): every pole and zero (pairs and real roots) times `scale`, b1 times `scale`;
// the damping ratios and the DC gain kept (the first-pass model of notes/004.md sec. 9 item 1,
// 004 sec. 4.5). @param scale > 0
forcerec::TransferModel frequency_scaled(const forcerec::TransferModel& model, double scale);
// The model realized in scaled modal form and discretized at kOversampling x sample_rate_hz.
forcerec::DiscreteModel oversampled_model(const forcerec::TransferModel& model,
                                          double sample_rate_hz);

// One cut of `cuts.list`.
struct CutSpec {
  std::string name;
  milling::Operation operation = milling::Operation::kDownMilling;
  double spindle_rpm = 0.0;
  double axial_depth_mm = 0.0;
  double radial_immersion_mm = 0.0;
  double feed_per_tooth_mm = 0.0;
};

// The optional `cuts:` block.
struct CutsSpec {
  double fs_hz = 10240.0;
  double duration_s = 3.0;
  double air_s = 0.5;    // not engaged before it
  double noise_N = 0.1;  // white noise std on each axis output (R = 0.01 N^2: 004 has 0.007-0.02)
  // notes/004.md sec. 9 item 3 (the prototype: Fy from -15.5 to 31 N in a slot).
  CuttingCoefficients coefficients{8.0e8, 1.7e8, 2.8e4, 3.1e4};
  double runout_um = 0.0;                // tooth 1 stands out radially by this
  std::optional<double> drift_fn_scale;  // hammer-before tests with frequency_scaled(model, it)
  std::vector<CutSpec> list;
  // From the spec's tool (checked present by parse_cuts).
  int teeth = 0;
  double radius_m = 0.0;
};

struct ForcerecSynthSpec : KindSpec {
  std::string folder = "forcerec";
  double fs_hz = 51200.0;
  std::vector<char> axes{'x', 'y'};
  int hits = 5;
  double hit_spacing_s = 0.5;
  double peak_N = 200.0;
  double pulse_s = 2.5e-4;
  double bounce_fraction = 0.15;  // of the peak
  double bounce_delay_s = 2.5e-3;
  double noise_N = 0.02;  // white noise std on both channels
  double band_lo_hz = 50.0, band_hi_hz = 3500.0;
  double hammer_scale_N_per_V = 444.4;
  double dyno_scale_N_per_V = 100.0;
  std::optional<CutsSpec> cuts;
};

// Reads `forcerec.cuts` (node `cuts`, present) into s.cuts; errors through r keyed
// `forcerec.cuts.<key>` (list entries `forcerec.cuts.list[i].<key>`). s.axes must be read.
void parse_cuts(const YAML::Node& cuts, const SynthContext& ctx, ForcerecSynthSpec& s,
                YamlReader& r);

// The force on the workpiece (N) along the dynamometer's x and y at time t of a rigid-tool cut
// (forcerec_cut_synth.cpp's file comment), spindle angle theta_1 = 2 pi rpm / 60 t.
// @param engagement the ramp factor in [0, 1] (0 before air_s)
Eigen::Vector2d cut_force_on_workpiece_N(const CutsSpec& cuts, const CutSpec& cut, double t_s,
                                         double engagement);

// Writes <folder>/cuts/<name> for every cut of s.cuts (present) and their truth entries; the
// hammer tests <folder>/hammer/<axis> are written by the caller. Returns the tests written.
int write_cuts(const ForcerecSynthSpec& s, SynthContext& ctx);

}  // namespace chatterlab::app::forcerec_synth
