#include "app/kinds/cut/cut_synth.h"

#include <cmath>
#include <fstream>
#include <random>

#include "analysis/common/check.h"
#include "analysis/common/constants.h"
#include "analysis/common/modal_parameters.h"
#include "analysis/common/summary.h"
#include "analysis/milling/simulation_options.h"
#include "analysis/sync/cut_synth.h"
#include "app/core/signals.h"

namespace chatterlab::app {
namespace {

std::vector<double> numbers(const YAML::Node& n, const std::string& path, YamlReader& r) {
  std::vector<double> v;
  try {
    if (n.IsScalar()) {
      v.push_back(n.as<double>());
    } else if (n.IsSequence()) {
      for (const auto& e : n) v.push_back(e.as<double>());
    } else {
      r.error(path, "must be a number or a list of numbers");
    }
  } catch (const YAML::Exception&) {
    r.error(path, "must be a number or a list of numbers");
  }
  for (double x : v) {
    if (!std::isfinite(x)) {
      r.error(path, "must be finite numbers (.inf and .nan are refused)");
      return {};
    }
  }
  return v;
}

// Samples per spindle revolution (whole: read_cut_synth checked it).
int samples_per_revolution(const CutSynthSpec& s) {
  return static_cast<int>(std::lround(s.fs_hz * 60.0 / s.spindle_rpm));
}

}  // namespace

CutSynthSpec read_cut_synth(const YAML::Node& n, const SynthContext& ctx, YamlReader& r) {
  CutSynthSpec s;
  const std::string p = "cut";
  r.check_keys(n,
               {"sample_rate_hz", "spindle_rpm", "feed_per_tooth_mm", "radial_immersion_mm",
                "operation", "modal", "coefficients", "sensor_to_tip", "scale_m_per_V", "noise_m",
                "runout_um", "runout_angle_deg", "out_of_round_um", "air_revolutions", "tests"},
               p);
  s.fs_hz = r.optional_double(n, "sample_rate_hz", p).value_or(s.fs_hz);
  s.spindle_rpm = r.optional_double(n, "spindle_rpm", p).value_or(s.spindle_rpm);
  s.feed_per_tooth_m =
      r.optional_double(n, "feed_per_tooth_mm", p).value_or(s.feed_per_tooth_m / kMmToM) * kMmToM;
  s.radial_immersion_m =
      r.optional_double(n, "radial_immersion_mm", p).value_or(s.radial_immersion_m / kMmToM) *
      kMmToM;
  s.operation = r.optional_string(n, "operation", p).value_or(s.operation);
  if (s.operation != "up-milling" && s.operation != "down-milling") {
    r.error("cut.operation", "must be up-milling or down-milling");
  }
  const YAML::Node modal = n["modal"];
  if (!modal || !modal.IsMap()) {
    r.error("cut.modal", "must be {m_kg, c_kg_s, k_N_m}");
  } else {
    s.modal.m_kg = r.required_double(modal, "m_kg", "cut.modal");
    s.modal.c_kg_s = r.required_double(modal, "c_kg_s", "cut.modal");
    s.modal.k_N_m = r.required_double(modal, "k_N_m", "cut.modal");
  }
  const YAML::Node k = n["coefficients"];
  if (!k || !k.IsMap() || !k["Kt_N_m2"] || !k["Kr_N_m2"]) {
    r.error("cut.coefficients", "must be {Kt_N_m2: [one per tooth], Kr_N_m2: [one per tooth]}");
  } else {
    s.Kt_N_m2 = numbers(k["Kt_N_m2"], "cut.coefficients.Kt_N_m2", r);
    s.Kr_N_m2 = numbers(k["Kr_N_m2"], "cut.coefficients.Kr_N_m2", r);
  }
  s.sensor_to_tip = r.optional_double(n, "sensor_to_tip", p).value_or(s.sensor_to_tip);
  s.scale_m_per_V = r.optional_double(n, "scale_m_per_V", p).value_or(s.scale_m_per_V);
  s.noise_m = r.optional_double(n, "noise_m", p).value_or(s.noise_m);
  s.runout_m = r.optional_double(n, "runout_um", p).value_or(s.runout_m * 1e6) * 1e-6;
  s.runout_angle_deg = r.optional_double(n, "runout_angle_deg", p).value_or(s.runout_angle_deg);
  if (n["out_of_round_um"]) {
    s.out_of_round_m.clear();
    for (double v : numbers(n["out_of_round_um"], "cut.out_of_round_um", r)) {
      s.out_of_round_m.push_back(v * 1e-6);
    }
  }
  // Revolutions in air before the cut (docs/format/synth-spec.md): 2 to 1000.
  constexpr long kMaxAirRevolutions = 1000;
  s.air_revolutions = static_cast<int>(
      r.optional_int(n, "air_revolutions", p, 2, kMaxAirRevolutions).value_or(s.air_revolutions));
  const double per_rev = s.fs_hz * 60.0 / s.spindle_rpm;
  if (!(std::abs(per_rev - std::round(per_rev)) <= 1e-9 * per_rev) || per_rev < 15.5) {
    r.error("cut.sample_rate_hz", "sample_rate_hz * 60 / spindle_rpm = " + synth_number(per_rev) +
                                      ": must be a whole number of samples per revolution (>= 16)");
  }
  if (ctx.tool && (static_cast<int>(s.Kt_N_m2.size()) != ctx.tool->teeth ||
                   static_cast<int>(s.Kr_N_m2.size()) != ctx.tool->teeth)) {
    r.error("cut.coefficients",
            "need one Kt_N_m2 and one Kr_N_m2 per tooth (" + std::to_string(ctx.tool->teeth) + ")");
  }
  const YAML::Node tests = n["tests"];
  if (!tests || !tests.IsSequence() || tests.size() == 0) {
    r.error("cut.tests", "must be a list of {name, axial_depth_mm, ..., offset_angle_deg}");
    return s;
  }
  if (tests.size() > 100) {  // one test folder each (docs/format/synth-spec.md)
    r.error("cut.tests", "has " + std::to_string(tests.size()) + " tests: at most 100");
    return s;
  }
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const YAML::Node t = tests[i];
    const std::string tp = "cut.tests[" + std::to_string(i) + "]";
    r.check_keys(
        t, {"name", "axial_depth_mm", "revolutions_per_mm", "duration_s", "offset_angle_deg"}, tp);
    CutTestSynth c;
    c.name = r.required_string(t, "name", tp);
    const auto depth = r.optional_number_or_pair(t, "axial_depth_mm", tp);
    if (!depth) {
      r.error(tp + ".axial_depth_mm", "is missing");
    } else {
      c.depth_start_m = depth->first * kMmToM;
      c.depth_end_m = depth->second * kMmToM;
    }
    c.revolutions_per_mm = r.optional_double(t, "revolutions_per_mm", tp);
    c.duration_s = r.optional_double(t, "duration_s", tp);
    if (depth && depth->first != depth->second && !c.revolutions_per_mm) {
      r.error(tp + ".revolutions_per_mm", "is required for a ramped depth");
    }
    if (depth && depth->first == depth->second && !c.duration_s) {
      r.error(tp + ".duration_s", "is required for a constant depth");
    }
    c.offset_angle_deg = r.optional_double(t, "offset_angle_deg", tp);
    s.tests.push_back(c);
  }
  return s;
}

int write_cut_tests(const CutSynthSpec& s, SynthContext& ctx) {
  CHATTERLAB_CHECK(ctx.tool.has_value(), "cut tests are written with the spec's tool");
  const int teeth = ctx.tool->teeth;
  const int P = samples_per_revolution(s);
  milling::SimulationOptions o;
  o.teeth = teeth;
  o.radius_m = ctx.tool->radius_m();
  o.modal_x = s.modal;
  for (int p = 0; p < teeth; ++p) {
    o.coefficients.push_back(milling::cutting_coefficients(s.Kt_N_m2[static_cast<std::size_t>(p)],
                                                           s.Kr_N_m2[static_cast<std::size_t>(p)]));
  }
  o.operation = s.operation == "down-milling" ? milling::Operation::kDownMilling
                                              : milling::Operation::kUpMilling;
  o.spindle_rpm = s.spindle_rpm;
  o.feed_per_tooth_m = s.feed_per_tooth_m;
  o.radial_immersion_m = s.radial_immersion_m;
  // Every k-th simulation step is a sample, at least 800 steps per tooth pass (000 sec. 5.2).
  o.steps_per_tooth = sync::sampled_steps_per_tooth(P, teeth);

  int written = 0;
  for (std::size_t i = 0; i < s.tests.size(); ++i) {
    const CutTestSynth& c = s.tests[i];
    const bool ramp = c.depth_start_m != c.depth_end_m;
    o.depth =
        ramp ? milling::DepthProfile::ramp(c.depth_start_m, c.depth_end_m, *c.revolutions_per_mm)
             : milling::DepthProfile::constant(
                   c.depth_start_m,
                   std::max(1, static_cast<int>(std::ceil(*c.duration_s * s.spindle_rpm / 60))));
    double offset_deg = 0.0;
    if (c.offset_angle_deg) {
      offset_deg = *c.offset_angle_deg;
    } else {
      std::mt19937_64 draw(ctx.stream_seed("synth.cut.offset_angle", i));
      offset_deg = 360.0 * static_cast<double>(draw() >> 11) * 0x1.0p-53;
    }
    sync::CutRecordSpec r;
    r.cut = o;
    r.fs_hz = s.fs_hz;
    r.air_revolutions = s.air_revolutions;
    r.tail_revolutions = 2;  // two revolutions after the cut window
    r.offset_angle_deg = offset_deg;
    r.noise_tip_m = s.noise_m;
    r.sensor_to_tip = s.sensor_to_tip;
    r.contour.eccentricity_m = s.runout_m;
    r.contour.eccentricity_angle_rad = s.runout_angle_deg * kDegToRad;
    r.contour.harmonic_m = s.out_of_round_m;  // phases drawn from the test's seed
    r.seed = ctx.stream_seed("synth.cut", i);
    const sync::CutRecord rec = sync::synthesize_cut_record(r);
    if (!rec.summary.ok()) {
      throw InputError("synth: cut test '" + c.name + "': " + rec.summary.message);
    }
    // Volts: the test's channel calibration (scale, gap offset) gives the sensor metres back.
    const Eigen::VectorXd xv = (rec.x_sensor_m.array() - s.gap_offset_m) / s.scale_m_per_V;
    const Eigen::VectorXd yv = (rec.y_sensor_m.array() - s.gap_offset_m) / s.scale_m_per_V;
    const auto dir = ctx.out / "cuts" / c.name;
    std::filesystem::create_directories(dir);
    write_signals(dir / "signals.f32", {"x", "y", "tach"}, {&xv, &yv, &rec.tach_V});
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "cut";
    y << YAML::Key << "operation" << YAML::Value << s.operation;
    y << YAML::Key << "spindle_rpm" << YAML::Value << s.spindle_rpm;
    y << YAML::Key << "feed_per_tooth_mm" << YAML::Value << s.feed_per_tooth_m / kMmToM;
    y << YAML::Key << "radial_immersion_mm" << YAML::Value << s.radial_immersion_m / kMmToM;
    y << YAML::Key << "axial_depth_mm" << YAML::Value;
    if (ramp) {
      y << YAML::Flow << YAML::BeginSeq << c.depth_start_m / kMmToM << rec.depth_end_m / kMmToM
        << YAML::EndSeq;
    } else {
      y << c.depth_start_m / kMmToM;
    }
    y << YAML::Key << "cut_window_s" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << rec.cut_start_s << rec.cut_end_s << YAML::EndSeq;
    // From the record's first sample (t = 0, written 0.0 as synth always has).
    y << YAML::Key << "air_window_s" << YAML::Value << YAML::Flow << YAML::BeginSeq << "0.0"
      << rec.air_end_s << YAML::EndSeq;
    y << YAML::Key << "sample_rate_hz" << YAML::Value << s.fs_hz;
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "signals.f32" << YAML::Key << "channels" << YAML::Value << YAML::Flow
      << YAML::BeginSeq << "x"
      << "y"
      << "tach" << YAML::EndSeq << YAML::EndMap;
    y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
    for (const char* sensor : {"x", "y"}) {
      y << YAML::Key << sensor << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "scale" << YAML::Value << s.scale_m_per_V << YAML::Key << "offset" << YAML::Value
        << s.gap_offset_m << YAML::EndMap;
    }
    y << YAML::Key << "tach" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "threshold" << YAML::Value << 2.5 << YAML::EndMap << YAML::EndMap;
    y << YAML::Key << "sensor_to_tip" << YAML::Value << s.sensor_to_tip << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    ctx.truth.tests["cuts/" + c.name] = synth_numbers({{"offset_angle_deg", offset_deg}});
    ++written;
  }
  ctx.truth.top["modal"] =
      synth_numbers({{"m_kg", s.modal.m_kg}, {"c_kg_s", s.modal.c_kg_s}, {"k_N_m", s.modal.k_N_m}});
  std::vector<std::pair<std::string, double>> k;
  for (int p = 0; p < teeth; ++p) {
    const std::string n = std::to_string(p + 1);
    k.emplace_back("Kt" + n + "_N_m2", s.Kt_N_m2[static_cast<std::size_t>(p)]);
    k.emplace_back("Kr" + n + "_N_m2", s.Kr_N_m2[static_cast<std::size_t>(p)]);
  }
  ctx.truth.top["coefficients"] = synth_numbers(k);
  return written;
}

}  // namespace chatterlab::app
