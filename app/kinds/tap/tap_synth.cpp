#include "app/kinds/tap/tap_synth.h"

#include <cmath>
#include <fstream>
#include <random>

#include "analysis/common/summary.h"
#include "analysis/frf/modal_response.h"
#include "app/core/signals.h"
#include "app/core/yaml_load.h"
#include "app/kinds/tap/tap_step.h"

namespace chatterlab::app {
TapSynthSpec read_tap_synth(const YAML::Node& n, YamlReader& r) {
  TapSynthSpec s;
  r.check_keys(n,
               {"sample_rate_hz", "hits", "hit_spacing_s", "response", "noise_pct", "force_peak_N",
                "pulse_width_s", "axes"},
               "tap");
  s.fs_hz = r.optional_double(n, "sample_rate_hz", "tap").value_or(s.fs_hz);
  // Bounds stated in docs/format/synth-spec.md: a tap record of at most kMaxHits hits.
  constexpr long kMaxHits = 100;
  s.hits = static_cast<int>(r.optional_int(n, "hits", "tap", 1, kMaxHits).value_or(s.hits));
  s.hit_spacing_s = r.optional_double(n, "hit_spacing_s", "tap").value_or(s.hit_spacing_s);
  s.response = r.optional_string(n, "response", "tap").value_or(s.response);
  s.noise_pct = r.optional_double(n, "noise_pct", "tap").value_or(s.noise_pct);
  s.force_peak_N = r.optional_double(n, "force_peak_N", "tap").value_or(s.force_peak_N);
  s.pulse_width_s = r.optional_double(n, "pulse_width_s", "tap").value_or(s.pulse_width_s);
  if (s.response != "acceleration" && s.response != "velocity" && s.response != "displacement") {
    r.error("tap.response", "must be acceleration, velocity or displacement");
  }
  if (s.hits < 1) r.error("tap.hits", "must be >= 1");
  if (!(s.fs_hz > 0)) r.error("tap.sample_rate_hz", "must be > 0");
  if (!(s.hit_spacing_s > 0.2)) r.error("tap.hit_spacing_s", "must be > 0.2 s");
  const YAML::Node axes = n["axes"];
  if (!axes || !axes.IsMap()) {
    r.error("tap.axes", "must map x and/or y to {modes: [{m_kg, c_kg_s, k_N_m}, ...]}");
    return s;
  }
  for (const auto& kv : axes) {
    if (!is_name_key(kv.first)) {
      r.error("tap.axes", "has a key that is not an axis name (x or y)");
      continue;
    }
    const auto axis = kv.first.Scalar();
    const std::string path = "tap.axes." + axis;
    if (axis != "x" && axis != "y") {
      r.error(path, "axis must be x or y");
      continue;
    }
    TapAxisSynth a;
    // 0: no double hit; else the 1-based hit that bounces.
    a.double_hit =
        static_cast<int>(r.optional_int(kv.second, "double_hit", path, 0, kMaxHits).value_or(0));
    const YAML::Node modes = kv.second["modes"];
    if (!modes || !modes.IsSequence() || modes.size() == 0) {
      r.error(path + ".modes", "must be a non-empty list of {m_kg, c_kg_s, k_N_m}");
      continue;
    }
    for (const auto& m : modes) {
      const double mk = r.required_double(m, "m_kg", path + ".modes");
      const double ck = r.required_double(m, "c_kg_s", path + ".modes");
      const double kk = r.required_double(m, "k_N_m", path + ".modes");
      try {
        a.modes.push_back(frf::mode_from_mck(mk, ck, kk));
      } catch (const InputError& e) {
        r.error(path + ".modes", e.what());
      }
    }
    s.axes[axis] = a;
  }
  return s;
}

int write_tap_tests(const TapSynthSpec& s, SynthContext& ctx) {
  int written = 0;
  for (const auto& [axis, a] : s.axes) {
    // One stream per axis (x: 0, y: 1), the same whether or not the other axis is written.
    const std::uint64_t axis_seed = ctx.stream_seed("synth.tap", axis == "x" ? 0 : 1);
    std::mt19937_64 rng(axis_seed);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05), gain(0.85, 1.15);
    std::vector<frf::HammerPulse> pulses;
    for (int i = 0; i < s.hits; ++i) {
      const double t = 0.2 + i * s.hit_spacing_s + jitter(rng);
      pulses.push_back({t, s.force_peak_N * gain(rng), s.pulse_width_s});
      if (a.double_hit == i + 1) {  // the hammer bounces 3 ms later at a third of the force
        pulses.push_back({t + 3e-3, s.force_peak_N / 3, s.pulse_width_s});
      }
    }
    const auto n =
        static_cast<Eigen::Index>(std::llround((0.2 + s.hits * s.hit_spacing_s) * s.fs_hz));
    frf::TapSynthesisOptions opt;
    opt.force_noise_fraction = s.noise_pct / 100.0 * 0.1;  // a hammer channel is cleaner
    opt.response_noise_fraction = s.noise_pct / 100.0;
    opt.seed = axis_seed;
    const frf::TapRecord rec =
        frf::synthesize_tap_record(a.modes, pulses, s.fs_hz, n, response_kind_of(s.response), opt);
    const auto dir = ctx.out / "tap" / axis;
    std::filesystem::create_directories(dir);
    write_signals(dir / "hits.csv", {"force", "response"}, {&rec.force_n, &rec.response});
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "tap";
    y << YAML::Key << "axis" << YAML::Value << axis;
    y << YAML::Key << "sample_rate_hz" << YAML::Value << s.fs_hz;
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "hits.csv" << YAML::EndMap;
    y << YAML::Key << "response" << YAML::Value << s.response;
    y << YAML::Key << "hits" << YAML::Value << "auto" << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    ++written;
    YAML::Node modes(YAML::NodeType::Sequence);
    for (const auto& m : a.modes) {
      modes.push_back(synth_numbers({{"fn_hz", m.fn_hz},
                                     {"zeta", m.zeta},
                                     {"m_kg", m.m_kg},
                                     {"c_kg_s", m.c_kg_s},
                                     {"k_N_m", m.k_N_m}}));
    }
    ctx.truth.tests["tap/" + axis]["modes"] = modes;
  }
  // Campaign-wide `modal`: the first mode of x (cut tests, written after, replace it with their
  // modal parameters in the cut, the values their identification targets: cut_synth.cpp).
  const auto x = s.axes.find("x");
  if (x != s.axes.end()) {
    const auto& m = x->second.modes.front();
    ctx.truth.top["modal"] =
        synth_numbers({{"m_kg", m.m_kg}, {"c_kg_s", m.c_kg_s}, {"k_N_m", m.k_N_m}});
  }
  return written;
}

}  // namespace chatterlab::app
