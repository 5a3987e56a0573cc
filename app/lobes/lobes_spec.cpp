#include "app/lobes/lobes_spec.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "analysis/common/summary.h"
#include "app/core/spec_fields.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"

namespace chatterlab::app {
namespace {

constexpr double kMm = 1e-3;

// modal.x or modal.y: {modes: [{m_kg, c_kg_s, k_N_m}, ...]} as the format writes it (an empty
// list: a rigid axis), or one mode {m_kg, c_kg_s, k_N_m} as a simulation spec writes it.
std::vector<ModalParameters> read_axis(const YAML::Node& n, YamlReader& r,
                                       const std::string& path) {
  std::vector<ModalParameters> modes;
  if (!n) return modes;  // an absent axis is rigid (docs/format/lobes.md)
  if (!n.IsMap()) {
    r.error(path, "must be {modes: [{m_kg, c_kg_s, k_N_m}, ...]} or {m_kg, c_kg_s, k_N_m}");
    return modes;
  }
  if (!n["modes"]) {
    modes.push_back(read_modal_parameters(n, r, path));
    return modes;
  }
  r.check_keys(n, {"modes"}, path);
  const YAML::Node list = n["modes"];
  if (!list.IsSequence()) {
    r.error(path + ".modes", "must be a list of {m_kg, c_kg_s, k_N_m}");
    return modes;
  }
  if (list.size() > static_cast<std::size_t>(kMaxModesPerAxis)) {
    r.error(path + ".modes", "has " + std::to_string(list.size()) + " modes: at most " +
                                 std::to_string(kMaxModesPerAxis));
    return modes;
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string p = path + ".modes[" + std::to_string(i) + "]";
    if (!list[i].IsMap()) {
      r.error(p, "must be {m_kg, c_kg_s, k_N_m}");
      continue;
    }
    modes.push_back(read_modal_parameters(list[i], r, p));
  }
  return modes;
}

}  // namespace

LobesSpec load_lobes_spec(const std::filesystem::path& file) {
  const std::string label = file.filename().string();
  const YAML::Node root = load_yaml_file_or_throw(file, label);
  YamlReader r(label);
  LobesSpec s;
  lobes::LobesInput& in = s.input;
  if (!root.IsMap()) throw InputError(label + ": must be a YAML mapping of keys");
  r.check_keys(root, {"format", "tool", "modal", "coefficients", "cut", "spindle_rpm", "speeds",
                      "max_depth_mm", "methods", "steps_per_tooth"});
  const auto format = r.required_string(root, "format");
  if (!format.empty() && format != "chatterlab-lobes/1") {
    r.error("format", "'" + format + "': must be 'chatterlab-lobes/1'");
  }
  const YAML::Node tool = root["tool"];
  if (!tool || !tool.IsMap()) {
    r.error("tool", "must be {teeth, radius_mm}");
  } else {
    r.check_keys(tool, {"teeth", "radius_mm", "helix_deg"}, "tool");
    if (const auto teeth = r.required_int(tool, "teeth", "tool", 1, milling::kMaxTeeth)) {
      in.teeth = static_cast<int>(*teeth);
    } else {
      in.teeth = 0;
    }
    in.radius_m = r.required_double(tool, "radius_mm", "tool") * kMm;
    if (!(in.radius_m > 0)) r.error("tool.radius_mm", "must be > 0");
  }
  const YAML::Node modal = root["modal"];
  if (!modal || !modal.IsMap()) {
    r.error("modal", "must be {m_kg, c_kg_s, k_N_m} or {x: {modes: [...]}, y: {modes: [...]}}");
  } else if (modal["x"] || modal["y"]) {
    r.check_keys(modal, {"x", "y"}, "modal");
    in.x_modes = read_axis(modal["x"], r, "modal.x");
    in.y_modes = read_axis(modal["y"], r, "modal.y");
    if (in.x_modes.empty() && in.y_modes.empty()) {
      r.error("modal", "has no mode on either axis: give at least one");
    }
  } else {
    const ModalParameters m = read_modal_parameters(modal, r, "modal");
    in.x_modes = {m};
    in.y_modes = {m};
  }
  const YAML::Node k = root["coefficients"];
  if (!k || !k.IsMap()) {
    r.error("coefficients", "must be {Kt_N_m2: ..., Kr_N_m2: ...}");
  } else {
    r.check_keys(k, {"Kt_N_m2", "Kr_N_m2"}, "coefficients");
    in.Kt_N_m2 = read_per_tooth(k, "Kt_N_m2", in.teeth, milling::kMaxTeeth, r);
    in.Kr_N_m2 = read_per_tooth(k, "Kr_N_m2", in.teeth, milling::kMaxTeeth, r);
  }
  const YAML::Node cut = root["cut"];
  if (!cut || !cut.IsMap()) {
    r.error("cut", "must be {operation, radial_immersion_mm}");
  } else {
    r.check_keys(cut, {"operation", "radial_immersion_mm"}, "cut");
    const std::string op = r.optional_string(cut, "operation", "cut").value_or("up-milling");
    if (op != "up-milling" && op != "down-milling") {
      r.error("cut.operation", "must be up-milling or down-milling, got '" + op + "'");
    }
    in.operation =
        op == "down-milling" ? milling::Operation::kDownMilling : milling::Operation::kUpMilling;
    in.radial_immersion_m = r.required_double(cut, "radial_immersion_mm", "cut") * kMm;
    if (!(in.radial_immersion_m > 0)) r.error("cut.radial_immersion_mm", "must be > 0");
    if (in.radius_m > 0 && in.radial_immersion_m > 2 * in.radius_m) {
      r.error("cut.radial_immersion_mm", "must not exceed the tool diameter");
    }
  }
  const auto rpm = r.optional_number_or_pair(root, "spindle_rpm");
  if (!rpm && !root["spindle_rpm"]) r.error("spindle_rpm", "is missing");
  const long speeds = r.optional_int(root, "speeds", "", 1, kMaxLobeSpeeds).value_or(200);
  if (rpm) {
    if (!(rpm->first > 0) || !(rpm->second > 0)) {
      r.error("spindle_rpm", "must be > 0");
    } else if (rpm->first == rpm->second) {
      in.spindle_rpm = {rpm->first};
      if (root["speeds"] && speeds != 1) {
        r.warn("speeds", "is ignored: spindle_rpm is one speed");
      }
    } else if (rpm->first > rpm->second) {
      r.error("spindle_rpm", "must be [low, high] with low < high");
    } else if (speeds < 2) {
      r.error("speeds", "must be at least 2 for a range of spindle_rpm (its ends)");
    } else {
      const long n = std::max(speeds, 2L);
      for (long i = 0; i < n; ++i) {
        in.spindle_rpm.push_back(rpm->first +
                                 (rpm->second - rpm->first) * static_cast<double>(i) / (n - 1));
      }
    }
  }
  in.max_depth_m = r.optional_double(root, "max_depth_mm").value_or(10.0) * kMm;
  if (!(in.max_depth_m > 0) || in.max_depth_m > kMaxLobeDepthMm * kMm) {
    r.error("max_depth_mm", "must be > 0 and at most " + std::to_string(kMaxLobeDepthMm) + " mm");
  }
  if (root["methods"]) {
    const auto methods = r.string_list(root, "methods", false);
    s.semi_discretization = s.zoa = false;
    for (const auto& m : methods) {
      if (m == "semi-discretization") {
        s.semi_discretization = true;
      } else if (m == "zoa") {
        s.zoa = true;
      } else {
        r.error("methods", "'" + m + "': must be semi-discretization or zoa");
      }
    }
    if (!s.semi_discretization && !s.zoa && r.errors().empty()) {
      r.error("methods", "is empty: name semi-discretization, zoa or both");
    }
  }
  s.steps_per_tooth = static_cast<int>(
      r.optional_int(root, "steps_per_tooth", "", 2, kMaxLobeStepsPerTooth).value_or(0));
  const auto modes = static_cast<long long>(in.x_modes.size() + in.y_modes.size());
  if (s.steps_per_tooth > 0 && (s.steps_per_tooth + 2LL) * modes > lobes::kMaxDelayStates) {
    r.error("steps_per_tooth",
            std::to_string(s.steps_per_tooth) + " intervals with " + std::to_string(modes) +
                " modes: (steps_per_tooth + 2) x modes must be at most " +
                std::to_string(lobes::kMaxDelayStates) + " (the size of the eigenvalue problem)");
  }
  r.throw_if_errors();
  s.warnings = r.warnings();
  // The core's own checks (e.g. a tooth count the coefficients do not match), as an input error.
  try {
    lobes::validate(in);
  } catch (const std::exception& e) {
    throw InputError(label + ": " + e.what());
  }
  return s;
}

}  // namespace chatterlab::app
