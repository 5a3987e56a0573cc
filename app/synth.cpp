#include "app/synth.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/cutting/slot_synth.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/synth_cut.h"
#include "app/synth_tap.h"

namespace chatterlab::app {
namespace {

void throw_if_errors(const YamlReader& r) {
  if (r.errors().empty()) return;
  std::string msg;
  for (const auto& e : r.errors()) msg += (msg.empty() ? "" : "\n") + e;
  throw InputError(msg);
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p);
  out << text;
  if (!out) throw InputError(p.string() + ": cannot write");
}

struct DynoSpec {
  double rpm = 0, depth_m = 0, fs = 0, duration_s = 0, theta_dyn_deg = 0, noise_N = 0;
  double sensitivity = 1.0;
  std::pair<double, double> offsets{0, 0};
  std::vector<double> feeds_m;
  milling::CuttingCoefficients k;
};

DynoSpec read_dyno(const YAML::Node& n, YamlReader& r) {
  DynoSpec d;
  r.check_keys(n,
               {"spindle_rpm", "axial_depth_mm", "feeds_mm", "sample_rate_hz", "duration_s",
                "theta_dyn_deg", "sensitivity_V_per_N", "offsets_N", "noise_N", "coefficients"},
               "dyno");
  d.rpm = r.required_double(n, "spindle_rpm", "dyno");
  d.depth_m = r.required_double(n, "axial_depth_mm", "dyno") * 1e-3;
  d.fs = r.required_double(n, "sample_rate_hz", "dyno");
  d.duration_s = r.required_double(n, "duration_s", "dyno");
  d.theta_dyn_deg = r.optional_double(n, "theta_dyn_deg", "dyno").value_or(0.0);
  d.noise_N = r.optional_double(n, "noise_N", "dyno").value_or(0.0);
  d.sensitivity = r.optional_double(n, "sensitivity_V_per_N", "dyno").value_or(1.0);
  if (!(d.sensitivity > 0)) r.error("dyno.sensitivity_V_per_N", "must be > 0");
  d.offsets = r.optional_pair(n, "offsets_N", "dyno").value_or(std::make_pair(0.0, 0.0));
  const YAML::Node feeds = n["feeds_mm"];
  if (!feeds || !feeds.IsSequence() || feeds.size() < 2) {
    r.error("dyno.feeds_mm", "must be a list of at least two feeds per tooth (mm)");
  } else {
    for (const auto& f : feeds) d.feeds_m.push_back(f.as<double>() * 1e-3);
  }
  const YAML::Node k = n["coefficients"];
  if (!k || !k.IsMap()) {
    r.error("dyno.coefficients", "must be {Ktc_N_m2, Kte_N_m, Krc_N_m2, Kre_N_m}");
  } else {
    d.k.Kt_N_m2 = r.required_double(k, "Ktc_N_m2", "dyno.coefficients");
    d.k.Kte_N_m = r.required_double(k, "Kte_N_m", "dyno.coefficients");
    d.k.Kr_N_m2 = r.required_double(k, "Krc_N_m2", "dyno.coefficients");
    d.k.Kre_N_m = r.required_double(k, "Kre_N_m", "dyno.coefficients");
  }
  return d;
}

// Writes one dyno-slot test per feed; returns the number written.
int write_dyno_group(const DynoSpec& d, std::uint64_t seed, const std::filesystem::path& out,
                     SynthTruth& truth) {
  int written = 0;
  for (std::size_t i = 0; i < d.feeds_m.size(); ++i) {
    cutting::SlotRecordSpec s;
    s.spindle_rpm = d.rpm;
    s.feed_per_tooth_m = d.feeds_m[i];
    s.depth_m = d.depth_m;
    s.coefficients = d.k;
    s.theta_dyn_rad = d.theta_dyn_deg * kDegToRad;
    s.initial_tool_angle_rad = 0.7 + 0.9 * static_cast<double>(i);  // any phase at record start
    s.offset_x_N = d.offsets.first;
    s.offset_y_N = d.offsets.second;
    s.noise_std_N = d.noise_N;
    s.zero_noise_std_V = 0.02;
    s.fs_hz = d.fs;
    s.duration_s = d.duration_s;
    s.seed = seed + 101 * (i + 1);
    cutting::SlotRecord rec = cutting::generate_slot_record(s);
    // Written in volts: the test's channel scale (1 / sensitivity) calibrates them back to N.
    const Eigen::VectorXd fx_V = rec.Fx_N * d.sensitivity;
    const Eigen::VectorXd fy_V = rec.Fy_N * d.sensitivity;
    char name[32];
    std::snprintf(name, sizeof(name), "f%03d", static_cast<int>(std::lround(d.feeds_m[i] * 1e6)));
    const auto dir = out / "dyno" / name;
    std::filesystem::create_directories(dir);
    write_signals(dir / "forces.csv", {"Fx", "Fy", "zero"}, {&fx_V, &fy_V, &rec.zero_V});
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "dyno-slot";
    y << YAML::Key << "spindle_rpm" << YAML::Value << d.rpm;
    y << YAML::Key << "feed_per_tooth_mm" << YAML::Value << d.feeds_m[i] * kMToMm;
    y << YAML::Key << "axial_depth_mm" << YAML::Value << d.depth_m * kMToMm;
    y << YAML::Key << "sample_rate_hz" << YAML::Value << d.fs;
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "forces.csv" << YAML::EndMap;
    y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
    for (const char* force : {"Fx", "Fy"}) {
      y << YAML::Key << force << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale"
        << YAML::Value << 1.0 / d.sensitivity << YAML::EndMap;
    }
    y << YAML::Key << "zero" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "threshold" << YAML::Value << 2.5 << YAML::EndMap;
    y << YAML::EndMap << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    ++written;
  }
  truth.tests["dyno/"] = synth_numbers({{"Ktc_N_m2", d.k.Kt_N_m2},
                                        {"Kte_N_m", d.k.Kte_N_m},
                                        {"Krc_N_m2", d.k.Kr_N_m2},
                                        {"Kre_N_m", d.k.Kre_N_m},
                                        {"theta_dyn_deg", d.theta_dyn_deg}});
  return written;
}

}  // namespace

std::string synth_number(double v) {
  std::ostringstream s;
  s.precision(kSynthDigits);
  s << v;
  return s.str();
}

YAML::Node synth_numbers(const std::vector<std::pair<std::string, double>>& values) {
  YAML::Node n(YAML::NodeType::Map);
  for (const auto& [key, v] : values) n[key] = synth_number(v);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

void configure_synth_emitter(YAML::Emitter& e) {
  e.SetDoublePrecision(kSynthDigits);  // the same text as synth_number
}

void write_synth_yaml(const std::filesystem::path& path, const YAML::Emitter& e) {
  if (!e.good()) {
    throw std::logic_error(path.string() + ": YAML emitter: " + e.GetLastError());
  }
  write_text(path, std::string(e.c_str()) + "\n");
}

SynthSummary synthesize_campaign(const std::filesystem::path& spec_yaml,
                                 const std::filesystem::path& out_dir) {
  const std::string label = spec_yaml.filename().string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(spec_yaml.string());
  } catch (const YAML::Exception& e) {
    throw InputError(label + ": cannot read (" + std::string(e.what()) + ")");
  }
  YamlReader r(label);
  r.check_keys(root, {"format", "name", "description", "seed", "tool", "workpiece", "machine",
                      "tap", "dyno", "cut"});
  const auto format = r.required_string(root, "format");
  if (!format.empty() && format != "chatterlab-synth/1") {
    r.error("format", "'" + format + "': must be 'chatterlab-synth/1'");
  }
  SynthSummary summary;
  summary.campaign_name = r.required_string(root, "name");
  const auto seed = static_cast<std::uint64_t>(r.optional_double(root, "seed").value_or(1.0));
  const YAML::Node tool = root["tool"];
  if ((root["dyno"] || root["cut"]) && !tool) {
    r.error("tool", "is required when the spec has a dyno group or cut tests");
  }
  std::optional<DynoSpec> dyno;
  if (root["dyno"]) dyno = read_dyno(root["dyno"], r);
  std::optional<TapSynthSpec> tap;
  if (root["tap"]) tap = read_tap_synth(root["tap"], r);
  std::optional<CutSynthSpec> cut;
  if (root["cut"]) cut = read_cut_synth(root["cut"], r);
  throw_if_errors(r);

  std::filesystem::create_directories(out_dir);
  YAML::Emitter campaign;
  configure_synth_emitter(campaign);
  campaign << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "chatterlab-campaign/1";
  campaign << YAML::Key << "name" << YAML::Value << summary.campaign_name;
  if (root["description"]) {
    campaign << YAML::Key << "description" << YAML::Value << YAML::Literal
             << root["description"].as<std::string>();
  }
  if (tool) {
    campaign << YAML::Key << "tool" << YAML::Value << YAML::Flow << YAML::BeginMap;
    campaign << YAML::Key << "teeth" << YAML::Value << tool["teeth"].as<int>();
    campaign << YAML::Key << "radius_mm" << YAML::Value << tool["radius_mm"].as<double>();
    if (tool["helix_deg"]) {
      campaign << YAML::Key << "helix_deg" << YAML::Value << tool["helix_deg"].as<double>();
    }
    campaign << YAML::EndMap;
  }
  for (const char* key : {"workpiece", "machine"}) {
    if (root[key]) campaign << YAML::Key << key << YAML::Value << root[key].as<std::string>();
  }
  campaign << YAML::EndMap;
  write_synth_yaml(out_dir / "campaign.yaml", campaign);

  SynthTruth truth;
  if (tap) summary.tests_written += write_tap_tests(*tap, seed, out_dir, truth, !cut);
  if (dyno) summary.tests_written += write_dyno_group(*dyno, seed, out_dir, truth);
  if (cut) {
    summary.tests_written += write_cut_tests(
        *cut, tool["teeth"].as<int>(), tool["radius_mm"].as<double>() * 1e-3, seed, out_dir, truth);
  }
  YAML::Emitter t;
  configure_synth_emitter(t);
  t << YAML::Comment("Values used by chatterlab synth to write this campaign.");
  t << YAML::BeginMap;
  for (const auto& kv : truth.top) t << YAML::Key << kv.first << YAML::Value << kv.second;
  t << YAML::Key << "tests" << YAML::Value << truth.tests << YAML::EndMap;
  write_synth_yaml(out_dir / "truth.yaml", t);
  return summary;
}

}  // namespace chatterlab::app
