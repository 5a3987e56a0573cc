#include "app/simulate/simulation_spec.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "analysis/common/summary.h"
#include "app/core/spec_fields.h"
#include "app/core/yaml_load.h"
#include "app/core/yaml_reader.h"

namespace chatterlab::app {
namespace {

constexpr double kMm = 1e-3;
// Bounds of the spec, stated in docs/format/simulation.md (every count read is bounded so that a
// typo cannot start a run of days or exhaust memory).
constexpr long kMaxTeeth = 500;
constexpr long kMaxRevolutions = 1000000;
constexpr long kMaxStepsPerTooth = 100000;
constexpr double kMaxSteps = 1e9;  // revolutions x teeth x steps_per_tooth
constexpr std::size_t kMaxPoincareDepths = 100;

}  // namespace

SimulationSpec load_simulation_spec(const std::filesystem::path& file) {
  const std::string label = file.filename().string();
  const YAML::Node root = load_yaml_file_or_throw(file, label);
  YamlReader r(label);
  SimulationSpec s;
  if (!root.IsMap()) throw InputError(label + ": must be a YAML mapping of keys");
  r.check_keys(root,
               {"format", "tool", "modal", "coefficients", "cut", "chip_model", "steps_per_tooth",
                "inertial", "poincare_depths_mm", "switching", "euler_order", "detector_noise_m"});
  const auto format = r.required_string(root, "format");
  if (!format.empty() && format != "chatterlab-simulation/1") {
    r.error("format", "'" + format + "': must be 'chatterlab-simulation/1'");
  }
  const YAML::Node tool = root["tool"];
  if (!tool || !tool.IsMap()) {
    r.error("tool", "must be {teeth, radius_mm}");
  } else {
    r.check_keys(tool, {"teeth", "radius_mm", "helix_deg"}, "tool");
    if (const auto teeth = r.required_int(tool, "teeth", "tool", 1, kMaxTeeth)) {
      s.teeth = static_cast<int>(*teeth);
    }
    s.radius_m = r.required_double(tool, "radius_mm", "tool") * kMm;
    if (!(s.radius_m > 0)) r.error("tool.radius_mm", "must be > 0");
  }
  const YAML::Node modal = root["modal"];
  if (!modal || !modal.IsMap()) {
    r.error("modal", "must be {m_kg, c_kg_s, k_N_m} or {x: {...}, y: {...}}");
  } else if (modal["x"] || modal["y"]) {
    r.check_keys(modal, {"x", "y"}, "modal");
    s.x = read_modal_parameters(modal["x"], r, "modal.x");
    s.y = read_modal_parameters(modal["y"], r, "modal.y");
  } else {
    s.x = s.y = read_modal_parameters(modal, r, "modal");
  }
  const YAML::Node k = root["coefficients"];
  if (!k || !k.IsMap()) {
    r.error("coefficients", "must be {Kt_N_m2: ..., Kr_N_m2: ...}");
  } else {
    r.check_keys(k, {"Kt_N_m2", "Kr_N_m2"}, "coefficients");
    s.Kt_N_m2 = read_per_tooth(k, "Kt_N_m2", s.teeth, kMaxTeeth, r);
    s.Kr_N_m2 = read_per_tooth(k, "Kr_N_m2", s.teeth, kMaxTeeth, r);
  }
  const YAML::Node cut = root["cut"];
  if (!cut || !cut.IsMap()) {
    r.error("cut", "must be a mapping (operation, spindle_rpm, feed_per_tooth_mm, ...)");
  } else {
    r.check_keys(cut,
                 {"operation", "spindle_rpm", "feed_per_tooth_mm", "radial_immersion_mm",
                  "axial_depth_mm", "revolutions_per_mm", "revolutions"},
                 "cut");
    s.operation = r.optional_string(cut, "operation", "cut").value_or("up-milling");
    if (s.operation != "up-milling" && s.operation != "down-milling") {
      r.error("cut.operation", "must be up-milling or down-milling, got '" + s.operation + "'");
    }
    s.spindle_rpm = r.required_double(cut, "spindle_rpm", "cut");
    if (!(s.spindle_rpm > 0)) r.error("cut.spindle_rpm", "must be > 0");
    s.feed_per_tooth_m = r.required_double(cut, "feed_per_tooth_mm", "cut") * kMm;
    if (!(s.feed_per_tooth_m > 0)) r.error("cut.feed_per_tooth_mm", "must be > 0");
    s.radial_immersion_m = r.required_double(cut, "radial_immersion_mm", "cut") * kMm;
    if (!(s.radial_immersion_m > 0)) r.error("cut.radial_immersion_mm", "must be > 0");
    if (s.radius_m > 0 && s.radial_immersion_m > 2 * s.radius_m) {
      r.error("cut.radial_immersion_mm", "must not exceed the tool diameter");
    }
    if (auto d = r.optional_number_or_pair(cut, "axial_depth_mm", "cut")) {
      s.depth_start_m = d->first * kMm;
      s.depth_end_m = d->second * kMm;
      if (d->first < 0 || d->second < 0) r.error("cut.axial_depth_mm", "must be >= 0");
    } else if (!cut["axial_depth_mm"]) {
      r.error("cut.axial_depth_mm", "is missing");
    }
    s.revolutions_per_mm = r.optional_double(cut, "revolutions_per_mm", "cut");
    if (auto n = r.optional_int(cut, "revolutions", "cut", 1, kMaxRevolutions)) {
      s.revolutions = static_cast<int>(*n);
    }
    const bool ramp = s.depth_start_m != s.depth_end_m;
    if (ramp && !s.revolutions_per_mm) {
      r.error("cut.revolutions_per_mm", "is required when axial_depth_mm changes (the ramp rate)");
    }
    if (s.revolutions_per_mm && !(*s.revolutions_per_mm > 0)) {
      r.error("cut.revolutions_per_mm", "must be > 0");
    }
    if (!ramp && !s.revolutions) {
      r.error("cut.revolutions", "is required for a constant axial depth (run length)");
    }
  }
  s.chip_model = r.optional_string(root, "chip_model").value_or("traditional");
  if (s.chip_model != "traditional" && s.chip_model != "numerical") {
    r.error("chip_model", "must be traditional or numerical, got '" + s.chip_model + "'");
  }
  s.switching = r.optional_string(root, "switching").value_or("contact");
  if (s.switching != "contact" && s.switching != "angle-only") {
    r.error("switching", "must be contact or angle-only, got '" + s.switching + "'");
  }
  if (s.switching == "angle-only" && s.chip_model == "numerical") {
    r.error("switching", "angle-only applies to the traditional chip model only");
  }
  s.detector_noise_m = r.optional_double(root, "detector_noise_m").value_or(5e-7);
  if (!(s.detector_noise_m > 0)) r.error("detector_noise_m", "must be > 0");
  s.euler_order = r.optional_string(root, "euler_order").value_or("velocity-first");
  if (s.euler_order != "velocity-first" && s.euler_order != "position-first") {
    r.error("euler_order", "must be velocity-first or position-first, got '" + s.euler_order + "'");
  }
  s.steps_per_tooth = static_cast<int>(
      r.optional_int(root, "steps_per_tooth", "", 8, kMaxStepsPerTooth).value_or(800));
  // The run's length: revolutions (constant depth) or the ramp's revolutions.
  double revs = s.revolutions ? static_cast<double>(*s.revolutions) : 0.0;
  if (s.revolutions_per_mm && std::isfinite(*s.revolutions_per_mm)) {
    revs = std::max(revs, std::abs(s.depth_end_m - s.depth_start_m) / kMm * *s.revolutions_per_mm);
  }
  const double steps = revs * std::max(s.teeth, 1) * s.steps_per_tooth;
  if (steps > kMaxSteps) {
    r.error("cut", "asks for " + std::to_string(static_cast<long long>(revs)) + " revolutions, " +
                       std::to_string(steps) +
                       " integration steps (revolutions x teeth x steps_per_tooth): at most " +
                       std::to_string(static_cast<long long>(kMaxSteps)) + " are simulated");
  }
  if (const YAML::Node in = root["inertial"]; in) {
    r.check_keys(in, {"enabled", "eccentricity_m", "eccentricity_angle_rad"}, "inertial");
    try {
      s.inertial = in["enabled"] ? in["enabled"].as<bool>() : false;
    } catch (const YAML::Exception&) {
      r.error("inertial.enabled", "must be true or false");
    }
    s.eccentricity_m = r.optional_double(in, "eccentricity_m", "inertial").value_or(0.0);
    s.eccentricity_angle_rad =
        r.optional_double(in, "eccentricity_angle_rad", "inertial").value_or(0.0);
  }
  if (const YAML::Node p = root["poincare_depths_mm"]; p) {
    if (!p.IsSequence()) {
      r.error("poincare_depths_mm", "must be a list of depths in mm");
    } else {
      if (p.size() > kMaxPoincareDepths) {
        r.error("poincare_depths_mm", "has " + std::to_string(p.size()) + " depths: at most " +
                                          std::to_string(kMaxPoincareDepths));
      }
      try {
        for (const auto& e : p) s.poincare_depths_m.push_back(e.as<double>() * kMm);
      } catch (const YAML::Exception&) {
        r.error("poincare_depths_mm", "must be a list of depths in mm");
      }
      for (double d : s.poincare_depths_m) {
        if (!std::isfinite(d)) r.error("poincare_depths_mm", "must be finite numbers");
      }
    }
  }
  r.throw_if_errors();
  s.warnings = r.warnings();
  return s;
}

}  // namespace chatterlab::app
