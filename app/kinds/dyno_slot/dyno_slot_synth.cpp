#include "app/kinds/dyno_slot/dyno_slot_synth.h"

#include <cmath>
#include <cstdio>

#include "analysis/common/constants.h"
#include "analysis/cutting/slot_synth.h"
#include "app/core/signals.h"

namespace chatterlab::app {

DynoSynthSpec read_dyno_synth(const YAML::Node& n, YamlReader& r) {
  DynoSynthSpec d;
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
  // At most 100 feeds (one test folder each; docs/format/synth-spec.md).
  constexpr std::size_t kMaxFeeds = 100;
  if (!feeds || !feeds.IsSequence() || feeds.size() < 2 || feeds.size() > kMaxFeeds) {
    r.error("dyno.feeds_mm", "must be a list of 2 to 100 feeds per tooth (mm)");
  } else {
    for (std::size_t i = 0; i < feeds.size(); ++i) {
      double f = 0;
      if (!feeds[i].IsScalar() || !YAML::convert<double>::decode(feeds[i], f) ||
          !std::isfinite(f)) {
        r.error("dyno.feeds_mm", "must be a list of finite numbers (feeds per tooth, mm)");
        d.feeds_m.clear();
        break;
      }
      d.feeds_m.push_back(f * 1e-3);
    }
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
int write_dyno_tests(const DynoSynthSpec& d, SynthContext& ctx) {
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
    s.seed = ctx.stream_seed("synth.dyno", i);
    cutting::SlotRecord rec = cutting::generate_slot_record(s);
    // Written in volts: the test's channel scale (1 / sensitivity) calibrates them back to N.
    const Eigen::VectorXd fx_V = rec.Fx_N * d.sensitivity;
    const Eigen::VectorXd fy_V = rec.Fy_N * d.sensitivity;
    char name[32];
    std::snprintf(name, sizeof(name), "f%03d", static_cast<int>(std::lround(d.feeds_m[i] * 1e6)));
    const auto dir = ctx.out / "dyno" / name;
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
  ctx.truth.tests["dyno/"] = synth_numbers({{"Ktc_N_m2", d.k.Kt_N_m2},
                                            {"Kte_N_m", d.k.Kte_N_m},
                                            {"Krc_N_m2", d.k.Kr_N_m2},
                                            {"Kre_N_m", d.k.Kre_N_m},
                                            {"theta_dyn_deg", d.theta_dyn_deg}});
  return written;
}

}  // namespace chatterlab::app
