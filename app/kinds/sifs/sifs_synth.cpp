#include "app/kinds/sifs/sifs_synth.h"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>

#include "analysis/common/constants.h"
#include "analysis/common/summary.h"
#include "analysis/signal/harmonic_fit.h"
#include "app/core/checked_write.h"
#include "app/core/signals.h"

namespace chatterlab::app {
namespace {

namespace s = chatterlab::sifs;

const std::vector<std::string> kWashers = {"x1", "x2", "y1", "y2", "z1", "z2"};
constexpr const char* kAxes[3] = {"x", "y", "z"};
// The harmonics of the truth: h SF <= this x filter_rate_hz (format step 4's limit).
constexpr double kHarmonicLimit = 0.45;

// ---- reading -------------------------------------------------------------------------------

void positive(YamlReader& r, const std::string& key, double v) {
  if (!(v > 0) || !std::isfinite(v)) r.error(key, "must be > 0");
}
void non_negative(YamlReader& r, const std::string& key, double v) {
  if (!(v >= 0) || !std::isfinite(v)) r.error(key, "must be >= 0");
}
void read(YamlReader& r, const YAML::Node& n, const std::string& key, const std::string& path,
          double& out) {
  out = r.optional_double(n, key, path).value_or(out);
}
void read_int(YamlReader& r, const YAML::Node& n, const std::string& key, const std::string& path,
              int& out, int min) {
  const auto v = r.optional_double(n, key, path);
  if (!v) return;
  if (!(*v >= min) || *v != std::floor(*v) || *v > 1e6) {
    r.error(path + "." + key, "must be a whole number >= " + std::to_string(min));
    return;
  }
  out = static_cast<int>(*v);
}
void read_band(YamlReader& r, const YAML::Node& n, const std::string& path,
               std::array<double, 2>& out) {
  const auto b = r.optional_pair(n, "band_hz", path);
  if (!b) return;
  if (!(b->first >= 0 && b->second > b->first)) {
    r.error(path + ".band_hz", "must be [lo, hi] with 0 <= lo < hi");
    return;
  }
  out = {b->first, b->second};
}
YAML::Node mapping(const YAML::Node& n, const std::string& key, const std::string& path,
                   YamlReader& r) {
  const YAML::Node v = n[key];
  if (v && !v.IsMap()) {
    r.error(path + "." + key, "must be a mapping");
    return YAML::Node(YAML::NodeType::Map);
  }
  return v ? v : YAML::Node(YAML::NodeType::Map);
}

void read_matrix(const YAML::Node& n, YamlReader& r, Eigen::Matrix3d& C) {
  const YAML::Node m = n["calibration_matrix"];
  if (!m) return;
  const std::string key = "sifs.calibration_matrix";
  bool ok = m.IsSequence() && m.size() == 3;
  Eigen::Matrix3d v;
  for (std::size_t i = 0; ok && i < 3; ++i) {
    ok = m[i].IsSequence() && m[i].size() == 3;
    for (std::size_t j = 0; ok && j < 3; ++j) {
      try {
        v(static_cast<int>(i), static_cast<int>(j)) = m[i][j].as<double>();
        ok = std::isfinite(v(static_cast<int>(i), static_cast<int>(j)));
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
  }
  if (!ok) {
    r.error(key, "must be three rows of three numbers [[f_x from s_x, s_y, s_z], [...], [...]]");
    return;
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(v);
  const auto sv = svd.singularValues();
  if (!(sv[2] > 1e-9 * sv[0])) {
    r.error(key, "is singular (S = C^-1 is needed)");
    return;
  }
  C = v;
}

void read_plant(const YAML::Node& n, const std::string& path, YamlReader& r,
                std::vector<s::SensorMode>& out) {
  if (!n) return;
  r.check_keys(n, {"modes"}, path);
  const YAML::Node modes = n["modes"];
  if (!modes || !modes.IsSequence() || modes.size() == 0 || modes.size() > 20) {
    r.error(path + ".modes", "must be a list of 1 to 20 {fn_hz, zeta, alpha}");
    return;
  }
  std::vector<s::SensorMode> v;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::string p = path + ".modes[" + std::to_string(i) + "]";
    if (!modes[i].IsMap()) {
      r.error(p, "must be {fn_hz, zeta, alpha}");
      continue;
    }
    r.check_keys(modes[i], {"fn_hz", "zeta", "alpha"}, p);
    s::SensorMode m;
    m.fn_hz = r.required_double(modes[i], "fn_hz", p);
    m.zeta = r.required_double(modes[i], "zeta", p);
    m.alpha = r.required_double(modes[i], "alpha", p);
    if (!(m.fn_hz > 0)) r.error(p + ".fn_hz", "must be > 0");
    if (!(m.zeta > 0 && m.zeta < 1)) r.error(p + ".zeta", "must be in (0, 1)");
    if (!std::isfinite(m.alpha)) r.error(p + ".alpha", "must be a number");
    v.push_back(m);
  }
  out = v;
}

void read_static(const YAML::Node& n, YamlReader& r, SifsSynthSpec& spec) {
  const std::string p = "sifs.static";
  r.check_keys(n,
               {"sample_rate_hz", "step_N", "steps", "unloaded_s", "hold_s", "transition_s",
                "drift_N_per_min", "offset_N", "noise_N", "load_sign"},
               p);
  s::StaticSynthOptions& o = spec.stat;
  read(r, n, "sample_rate_hz", p, o.fs_hz);
  read(r, n, "step_N", p, o.step_n);
  read_int(r, n, "steps", p, o.steps, 1);
  read(r, n, "unloaded_s", p, o.unloaded_s);
  read(r, n, "hold_s", p, o.hold_s);
  read(r, n, "transition_s", p, o.transition_s);
  read(r, n, "drift_N_per_min", p, o.drift_n_per_min);
  read(r, n, "offset_N", p, o.offset_n);
  read(r, n, "noise_N", p, o.noise_n);
  positive(r, p + ".sample_rate_hz", o.fs_hz);
  positive(r, p + ".step_N", o.step_n);
  if (!(o.unloaded_s > 2 * o.settle_s + 0.5)) r.error(p + ".unloaded_s", "must be > 1 s");
  if (!(o.hold_s > 2 * o.settle_s + 0.5)) r.error(p + ".hold_s", "must be > 1 s");
  positive(r, p + ".transition_s", o.transition_s);
  non_negative(r, p + ".drift_N_per_min", o.drift_n_per_min);
  non_negative(r, p + ".offset_N", o.offset_n);
  non_negative(r, p + ".noise_N", o.noise_n);
  if (const YAML::Node ls = n["load_sign"]) {
    bool ok = ls.IsSequence() && ls.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) {
      try {
        const double v = ls[i].as<double>();
        ok = v == 1.0 || v == -1.0;
        spec.load_sign[i] = v;
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok) r.error(p + ".load_sign", "must be [x, y, z] of 1 or -1");
  }
}

void read_taps(const YAML::Node& n, YamlReader& r, SifsSynthSpec& spec) {
  const std::string p = "sifs.taps";
  r.check_keys(n,
               {"sample_rate_hz", "oversample", "hits", "hit_spacing_s", "window_s", "pretrigger_s",
                "force_N", "pulse_width_s", "noise_N", "hammer_noise_N", "cross_fraction",
                "offset_N", "hammer_scale_N_per_V", "band_hz", "modes"},
               p);
  s::TapSynthOptions& o = spec.tap;
  read(r, n, "sample_rate_hz", p, o.fs_hz);
  read_int(r, n, "oversample", p, o.oversample, 4);
  read_int(r, n, "hits", p, o.hits, 1);
  read(r, n, "hit_spacing_s", p, o.hit_spacing_s);
  read(r, n, "window_s", p, o.window_s);
  read(r, n, "pretrigger_s", p, o.pretrigger_s);
  if (const auto f = r.optional_pair(n, "force_N", p)) {
    o.peak_min_n = f->first;
    o.peak_max_n = f->second;
    if (!(f->first > 0 && f->second >= f->first)) {
      r.error(p + ".force_N", "must be [min, max] with 0 < min <= max");
    }
  }
  read(r, n, "pulse_width_s", p, o.pulse_width_s);
  read(r, n, "noise_N", p, o.noise_n);
  read(r, n, "hammer_noise_N", p, o.hammer_noise_n);
  read(r, n, "cross_fraction", p, o.cross_fraction);
  read(r, n, "offset_N", p, o.offset_n);
  read(r, n, "hammer_scale_N_per_V", p, spec.hammer_scale_N_per_V);
  read_band(r, n, p, spec.tap_band_hz);
  read_int(r, n, "modes", p, spec.tap_modes, 1);
  positive(r, p + ".sample_rate_hz", o.fs_hz);
  if (!(o.pretrigger_s >= 0.02)) r.error(p + ".pretrigger_s", "must be >= 0.02 s");
  if (!(o.window_s > o.pretrigger_s + 0.01)) {
    r.error(p + ".window_s", "must exceed pretrigger_s by > 10 ms");
  }
  if (!(o.hit_spacing_s >= o.window_s + 0.04)) {
    r.error(p + ".hit_spacing_s", "must be >= window_s + 0.04 s (windows never overlap)");
  }
  o.first_hit_s = o.pretrigger_s + 0.06;
  positive(r, p + ".pulse_width_s", o.pulse_width_s);
  non_negative(r, p + ".noise_N", o.noise_n);
  non_negative(r, p + ".hammer_noise_N", o.hammer_noise_n);
  non_negative(r, p + ".offset_N", o.offset_n);
  positive(r, p + ".hammer_scale_N_per_V", spec.hammer_scale_N_per_V);
  if (!(std::abs(o.cross_fraction) <= 1)) r.error(p + ".cross_fraction", "must be in [-1, 1]");
}

void read_cuts(const YAML::Node& n, const SynthContext& ctx, YamlReader& r, SifsSynthSpec& spec) {
  const std::string p = "sifs.cuts";
  r.check_keys(n,
               {"rpm",
                "sample_rate_hz",
                "oversample",
                "duration_s",
                "air_s",
                "entry_s",
                "exit_s",
                "tail_s",
                "operation",
                "axial_depth_mm",
                "radial_immersion_mm",
                "feed_per_tooth_mm",
                "coefficients",
                "runout_um",
                "runout_angle_deg",
                "unbalance",
                "noise_N",
                "drift_N_per_min",
                "offset_N",
                "dynamometer",
                "band_hz",
                "unbalance_harmonics"},
               p);
  s::CutSynthOptions& o = spec.cut;
  if (const YAML::Node rpm = n["rpm"]) {
    spec.rpm.clear();
    bool ok = rpm.IsSequence();
    for (std::size_t i = 0; ok && i < rpm.size(); ++i) {
      try {
        spec.rpm.push_back(rpm[i].as<double>());
        ok = spec.rpm.back() > 0 && spec.rpm.back() < 1e6;
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok) r.error(p + ".rpm", "must be a list of spindle speeds > 0 (rpm)");
    std::set<long long> ids;
    for (double v : spec.rpm) {
      if (!ids.insert(std::llround(v)).second) {
        r.error(p + ".rpm", synth_number(v) + " rpm is listed twice (tests are named by rpm)");
      }
    }
  }
  read(r, n, "sample_rate_hz", p, o.fs_hz);
  read_int(r, n, "oversample", p, o.oversample, 2);
  if (o.oversample % 2 != 0) r.error(p + ".oversample", "must be even");
  read(r, n, "duration_s", p, o.duration_s);
  read(r, n, "air_s", p, o.air_s);
  read(r, n, "entry_s", p, o.entry_s);
  read(r, n, "exit_s", p, o.exit_s);
  read(r, n, "tail_s", p, o.tail_s);
  const std::string op = r.optional_string(n, "operation", p).value_or("up-milling");
  if (op != "up-milling" && op != "down-milling") {
    r.error(p + ".operation", "must be up-milling or down-milling");
  }
  o.force.up_milling = op == "up-milling";
  read(r, n, "axial_depth_mm", p, spec.axial_depth_mm);
  read(r, n, "radial_immersion_mm", p, spec.radial_immersion_mm);
  read(r, n, "feed_per_tooth_mm", p, spec.feed_per_tooth_mm);
  const YAML::Node k = mapping(n, "coefficients", p, r);
  const std::string kp = p + ".coefficients";
  r.check_keys(k, {"Ktc_N_m2", "Krc_N_m2", "Kte_N_m", "Kre_N_m", "Kac_N_m2", "Kae_N_m"}, kp);
  read(r, k, "Ktc_N_m2", kp, o.force.Ktc_N_m2);
  read(r, k, "Krc_N_m2", kp, o.force.Krc_N_m2);
  read(r, k, "Kte_N_m", kp, o.force.Kte_N_m);
  read(r, k, "Kre_N_m", kp, o.force.Kre_N_m);
  read(r, k, "Kac_N_m2", kp, o.force.Kac_N_m2);
  read(r, k, "Kae_N_m", kp, o.force.Kae_N_m);
  double runout_um = o.force.runout_m * 1e6;
  read(r, n, "runout_um", p, runout_um);
  o.force.runout_m = runout_um * 1e-6;
  read(r, n, "runout_angle_deg", p, o.force.runout_angle_deg);
  const YAML::Node u = mapping(n, "unbalance", p, r);
  const std::string up = p + ".unbalance";
  r.check_keys(u, {"m0e_kg_m", "phase_deg", "h2_fraction", "h2_phase_deg"}, up);
  read(r, u, "m0e_kg_m", up, o.m0e_kg_m);
  read(r, u, "phase_deg", up, o.unbalance_phase_deg);
  read(r, u, "h2_fraction", up, o.h2_fraction);
  read(r, u, "h2_phase_deg", up, o.h2_phase_deg);
  read(r, n, "noise_N", p, o.noise_n);
  read(r, n, "drift_N_per_min", p, o.drift_n_per_min);
  read(r, n, "offset_N", p, o.offset_n);
  const YAML::Node d = mapping(n, "dynamometer", p, r);
  const std::string dp = p + ".dynamometer";
  r.check_keys(d, {"angle_deg", "noise_N", "offset_N", "scale_N_per_V"}, dp);
  read(r, d, "angle_deg", dp, o.dyno_angle_deg);
  read(r, d, "noise_N", dp, o.dyno_noise_n);
  read(r, d, "offset_N", dp, o.dyno_offset_n);
  read(r, d, "scale_N_per_V", dp, spec.dyno_scale_N_per_V);
  read_band(r, n, p, spec.cut_band_hz);
  read_int(r, n, "unbalance_harmonics", p, spec.unbalance_harmonics, 1);

  positive(r, p + ".sample_rate_hz", o.fs_hz);
  positive(r, p + ".duration_s", o.duration_s);
  positive(r, p + ".entry_s", o.entry_s);
  positive(r, p + ".exit_s", o.exit_s);
  non_negative(r, p + ".tail_s", o.tail_s);
  if (!(o.air_s - o.margin_s > 0.15)) r.error(p + ".air_s", "must be > 0.2 s");
  positive(r, p + ".axial_depth_mm", spec.axial_depth_mm);
  positive(r, p + ".feed_per_tooth_mm", spec.feed_per_tooth_mm);
  for (const char* key : {"Ktc_N_m2", "Krc_N_m2", "Kte_N_m", "Kre_N_m", "Kac_N_m2", "Kae_N_m"}) {
    const double v = r.optional_double(k, key, kp).value_or(0.0);
    if (!std::isfinite(v)) r.error(kp + "." + key, "must be a number");
  }
  non_negative(r, p + ".runout_um", runout_um);
  non_negative(r, up + ".m0e_kg_m", o.m0e_kg_m);
  non_negative(r, up + ".h2_fraction", o.h2_fraction);
  non_negative(r, p + ".noise_N", o.noise_n);
  non_negative(r, p + ".drift_N_per_min", o.drift_n_per_min);
  non_negative(r, p + ".offset_N", o.offset_n);
  non_negative(r, dp + ".noise_N", o.dyno_noise_n);
  non_negative(r, dp + ".offset_N", o.dyno_offset_n);
  positive(r, dp + ".scale_N_per_V", spec.dyno_scale_N_per_V);
  const double steady_s = o.duration_s - o.tail_s - o.exit_s - o.air_s - o.entry_s - 2 * o.margin_s;
  for (double v : spec.rpm) {
    if (!(steady_s > 2.0 * 60.0 / v)) {
      r.error(p + ".duration_s", "leaves fewer than two revolutions of steady cutting at " +
                                     synth_number(v) +
                                     " rpm (steady part: duration_s - air_s - "
                                     "entry_s - exit_s - tail_s - 0.1 s)");
      break;
    }
  }
  if (spec.rpm.empty()) return;
  if (!ctx.tool) {
    if (!ctx.tool_given) {
      r.error("sifs", "needs the spec's tool ({teeth, radius_mm}) for its cut tests");
    }
    return;
  }
  o.force.teeth = ctx.tool->teeth;
  o.force.radius_m = ctx.tool->radius_m();
  o.force.helix_deg = ctx.tool->helix_deg.value_or(0.0);
  if (spec.radial_immersion_mm < 0) spec.radial_immersion_mm = ctx.tool->radius_mm;
  if (!(spec.radial_immersion_mm > 0 && spec.radial_immersion_mm <= 2 * ctx.tool->radius_mm)) {
    r.error(p + ".radial_immersion_mm", "must be in (0, tool diameter]");
  }
  if (!(o.force.helix_deg >= 0 && o.force.helix_deg < 80)) {
    r.error("tool.helix_deg", "must be in [0, 80) for the sifs cuts");
  }
  o.force.depth_m = spec.axial_depth_mm * 1e-3;
  o.force.radial_immersion_m = spec.radial_immersion_mm * 1e-3;
  o.force.feed_per_tooth_m = spec.feed_per_tooth_mm * 1e-3;
}

// ---- writing -------------------------------------------------------------------------------

std::string folder_id(const SifsSynthSpec& spec, const std::string& name) {
  return spec.folder + "/" + name;
}

std::string cut_name(double rpm) {
  char b[32];
  std::snprintf(b, sizeof b, "cut-n%05lld", std::llround(rpm));
  return b;
}

YAML::Node matrix(const Eigen::Matrix3d& m) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) n.push_back(synth_number_list({m(i, 0), m(i, 1), m(i, 2)}));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

double wrap_signed_deg(double a) {
  a = std::fmod(a, 360.0);
  if (a <= -180.0) a += 360.0;
  if (a > 180.0) a -= 360.0;
  return a;
}

void emit_pair(YAML::Emitter& y, const char* key, double a, double b) {
  y << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << a << b << YAML::EndSeq;
}

void emit_data(YAML::Emitter& y, double fs_hz, const std::string& file,
               const std::vector<std::string>& channels) {
  y << YAML::Key << "sample_rate_hz" << YAML::Value << fs_hz;
  y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
    << YAML::Value << file << YAML::Key << "channels" << YAML::Value << YAML::Flow
    << YAML::BeginSeq;
  for (const auto& c : channels) y << c;
  y << YAML::EndSeq << YAML::EndMap;
}

// channels: {name: {scale: ...}} for every channel.
void emit_scales(YAML::Emitter& y, const std::vector<std::pair<std::string, double>>& scales) {
  y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, scale] : scales) {
    y << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale"
      << YAML::Value << scale << YAML::EndMap;
  }
  y << YAML::EndMap;
}

std::vector<Eigen::VectorXd> washer_volts(const s::Washers& w, double scale) {
  std::vector<Eigen::VectorXd> v;
  for (int c = 0; c < 6; ++c) v.emplace_back(w.col(c) / scale);
  return v;
}

std::vector<const Eigen::VectorXd*> pointers(const std::vector<Eigen::VectorXd>& v) {
  std::vector<const Eigen::VectorXd*> p;
  for (const auto& x : v) p.push_back(&x);
  return p;
}

int write_static(const SifsSynthSpec& spec, SynthContext& ctx) {
  std::vector<std::pair<std::string, double>> scales;
  for (const auto& w : kWashers) scales.emplace_back(w, spec.washer_scale_N_per_V);
  for (int a = 0; a < 3; ++a) {
    s::StaticSynthOptions o = spec.stat;
    o.C = spec.C;
    o.load_sign = spec.load_sign[static_cast<std::size_t>(a)];
    o.seed = ctx.stream_seed("synth.sifs.static", static_cast<std::uint64_t>(a));
    const s::StaticSynth st = s::synthesize_static(static_cast<s::Axis>(a), o);
    const std::string id = folder_id(spec, std::string("static-") + kAxes[a]);
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    const auto cols = washer_volts(st.washers_n, spec.washer_scale_N_per_V);
    write_signals(dir / "static.f32", kWashers, pointers(cols));
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "sifs-static";
    y << YAML::Key << "axis" << YAML::Value << kAxes[a];
    emit_data(y, o.fs_hz, "static.f32", kWashers);
    emit_scales(y, scales);
    y << YAML::Key << "loads" << YAML::Value << YAML::BeginSeq;
    for (const auto& w : st.windows) {
      y << YAML::Flow << YAML::BeginSeq << w.start_s << w.end_s << w.load_n << YAML::EndSeq;
    }
    y << YAML::EndSeq << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    YAML::Node e(YAML::NodeType::Map);
    e["drift_N_per_min"] = synth_number_list(std::vector<double>(
        st.drift_n_per_min.data(), st.drift_n_per_min.data() + st.drift_n_per_min.size()));
    ctx.truth.tests[id] = e;
  }
  return 3;
}

int write_taps(const SifsSynthSpec& spec, SynthContext& ctx) {
  std::vector<std::string> names = {"hammer"};
  names.insert(names.end(), kWashers.begin(), kWashers.end());
  std::vector<std::pair<std::string, double>> scales = {{"hammer", spec.hammer_scale_N_per_V}};
  for (const auto& w : kWashers) scales.emplace_back(w, spec.washer_scale_N_per_V);
  for (int a = 0; a < 2; ++a) {
    s::TapSynthOptions o = spec.tap;
    o.C = spec.C;
    o.modes = a == 0 ? spec.plant_x : spec.plant_y;
    o.seed = ctx.stream_seed("synth.sifs.tap", static_cast<std::uint64_t>(a));
    const s::TapSynth tap = s::synthesize_tap(static_cast<s::Axis>(a), o);
    const std::string id = folder_id(spec, std::string("tap-") + kAxes[a]);
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    std::vector<Eigen::VectorXd> cols = {tap.hammer_n / spec.hammer_scale_N_per_V};
    for (auto& c : washer_volts(tap.washers_n, spec.washer_scale_N_per_V)) cols.push_back(c);
    write_signals(dir / "taps.f32", names, pointers(cols));
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "sifs-tap";
    y << YAML::Key << "axis" << YAML::Value << kAxes[a];
    emit_data(y, o.fs_hz, "taps.f32", names);
    emit_scales(y, scales);
    y << YAML::Key << "hits" << YAML::Value << YAML::BeginSeq;
    for (double t0 : tap.window_start_s) {
      y << YAML::Flow << YAML::BeginSeq << t0 << t0 + o.window_s << YAML::EndSeq;
    }
    y << YAML::EndSeq;
    emit_pair(y, "band_hz", spec.tap_band_hz[0], spec.tap_band_hz[1]);
    y << YAML::Key << "modes" << YAML::Value << spec.tap_modes << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);

    YAML::Node e(YAML::NodeType::Map);
    YAML::Node modes(YAML::NodeType::Sequence);
    // The synthetic plant has proportional damping: real residues (phase 0).
    for (const auto& m : o.modes) {
      modes.push_back(synth_numbers(
          {{"fn_hz", m.fn_hz}, {"zeta", m.zeta}, {"alpha", m.alpha}, {"residue_phase_deg", 0.0}}));
    }
    e["modes"] = modes;
    e["antiresonances_hz"] = synth_number_list(s::antiresonances_hz(o.modes));
    e["bandwidth_before_hz"] =
        synth_number(s::bandwidth_before_hz(o.modes, 0.5 * spec.filter_rate_hz));
    e["noise_var_N2"] = synth_number(tap.noise_var_n2);
    ctx.truth.tests[id] = e;
  }
  return 2;
}

void write_force_file(const std::filesystem::path& file, const s::CutSynth& cut, double fs_hz) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream out = open_for_writing(file);
  out << "t,fx,fy,fz\n";
  char line[128];
  for (Eigen::Index k = 0; k < cut.tip_force_n.rows(); ++k) {
    std::snprintf(line, sizeof line, "%.10g,%.10g,%.10g,%.10g\n", static_cast<double>(k) / fs_hz,
                  cut.tip_force_n(k, 0), cut.tip_force_n(k, 1), cut.tip_force_n(k, 2));
    out << line;
  }
  close_checked(out, file);
}

YAML::Node unbalance_node(const std::vector<s::UnbalanceTerm>& terms) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const auto& u : terms) {
    n.push_back(synth_numbers(
        {{"h", u.h}, {"amp_N", u.amp_n}, {"phase_deg", wrap_signed_deg(u.phase_deg)}}));
  }
  return n;
}

// The c_h (format step 6) of the true tip force over window_s, and G_true(j h Omega) c_h: a
// least-squares fit of the force file's rows over window_s, divided by the boxcar's sinc.
YAML::Node harmonics_node(const SifsSynthSpec& spec, const s::CutSynth& cut, double rpm) {
  const double fs = spec.cut.fs_hz, sf = rpm / 60.0;
  std::vector<int> h;
  for (int k = 1; k * sf <= kHarmonicLimit * spec.filter_rate_hz; ++k) h.push_back(k);
  const auto begin = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[0] * fs - 1e-6));
  const auto end = static_cast<Eigen::Index>(std::ceil(cut.harmonic_window_s[1] * fs - 1e-6));
  YAML::Node n(YAML::NodeType::Map);
  n["h"] = synth_number_list(std::vector<double>(h.begin(), h.end()));
  n["h"].SetStyle(YAML::EmitterStyle::Flow);
  for (int a = 0; a < 2; ++a) {
    const Eigen::VectorXd x = cut.tip_force_n.col(a);
    const signal::HarmonicFit fit = signal::fit_harmonics(x, fs, begin, end, sf, h);
    const auto& plant = a == 0 ? spec.plant_x : spec.plant_y;
    std::vector<double> re, im, mre, mim;
    for (std::size_t i = 0; i < h.size(); ++i) {
      // The file's rows are means over one sample interval (a centred boxcar): a fit of them
      // gives sinc(h SF / fs) c_h; the truth is the continuous force's c_h.
      const double xs = kPi * h[i] * sf / fs;
      const std::complex<double> c = fit.c(static_cast<Eigen::Index>(i)) / (std::sin(xs) / xs);
      const std::complex<double> m = s::sensor_response(plant, h[i] * sf) * c;
      re.push_back(c.real());
      im.push_back(c.imag());
      mre.push_back(m.real());
      mim.push_back(m.imag());
    }
    const std::string ax = kAxes[a];
    n[ax + "_re_N"] = synth_number_list(re);
    n[ax + "_im_N"] = synth_number_list(im);
    n[ax + "_meas_re_N"] = synth_number_list(mre);
    n[ax + "_meas_im_N"] = synth_number_list(mim);
    n[ax + "_mean_N"] = synth_number(fit.c0);
  }
  return n;
}

int write_cuts(const SifsSynthSpec& spec, SynthContext& ctx) {
  std::vector<std::string> names = kWashers;
  for (const char* d : {"dx", "dy", "dz"}) names.push_back(d);
  std::vector<std::pair<std::string, double>> scales;
  for (const auto& w : kWashers) scales.emplace_back(w, spec.washer_scale_N_per_V);
  for (const char* d : {"dx", "dy", "dz"}) scales.emplace_back(d, spec.dyno_scale_N_per_V);
  std::string prefix = spec.folder;
  for (auto& ch : prefix) {
    if (ch == '/') ch = '-';
  }
  int written = 0;
  for (std::size_t i = 0; i < spec.rpm.size(); ++i) {
    const double rpm = spec.rpm[i];
    s::CutSynthOptions o = spec.cut;
    o.C = spec.C;
    o.plant_x = spec.plant_x;
    o.plant_y = spec.plant_y;
    o.spindle_rpm = rpm;
    o.seed = ctx.stream_seed("synth.sifs.cut", i);
    std::mt19937_64 angle(ctx.stream_seed("synth.sifs.cut.theta1", i));
    o.theta1_deg = std::uniform_real_distribution<double>(0.0, 360.0)(angle);
    const s::CutSynth cut = s::synthesize_cut(o);
    const std::string name = cut_name(rpm);
    const std::string id = folder_id(spec, name);
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    auto cols = washer_volts(cut.washers_n, spec.washer_scale_N_per_V);
    for (int c = 0; c < 3; ++c) cols.emplace_back(cut.dyno_n.col(c) / spec.dyno_scale_N_per_V);
    write_signals(dir / "cut.f32", names, pointers(cols));
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "sifs-cut";
    y << YAML::Key << "spindle_rpm" << YAML::Value << rpm;
    emit_data(y, o.fs_hz, "cut.f32", names);
    emit_scales(y, scales);
    emit_pair(y, "air_window_s", cut.air_window_s[0], cut.air_window_s[1]);
    emit_pair(y, "cut_window_s", cut.cut_window_s[0], cut.cut_window_s[1]);
    y << YAML::Key << "taps" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "x"
      << YAML::Value << folder_id(spec, "tap-x") << YAML::Key << "y" << YAML::Value
      << folder_id(spec, "tap-y") << YAML::EndMap;
    y << YAML::Key << "dynamometer" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "channels" << YAML::Value << YAML::Flow << YAML::BeginSeq << "dx"
      << "dy"
      << "dz" << YAML::EndSeq << YAML::Key << "angle_deg" << YAML::Value << o.dyno_angle_deg
      << YAML::EndMap;
    emit_pair(y, "band_hz", spec.cut_band_hz[0], spec.cut_band_hz[1]);
    y << YAML::Key << "filter_rate_hz" << YAML::Value << spec.filter_rate_hz;
    y << YAML::Key << "unbalance_harmonics" << YAML::Value << spec.unbalance_harmonics;
    y << YAML::Key << "operation" << YAML::Value
      << (o.force.up_milling ? "up-milling" : "down-milling");
    y << YAML::Key << "axial_depth_mm" << YAML::Value << spec.axial_depth_mm;
    y << YAML::Key << "radial_immersion_mm" << YAML::Value << spec.radial_immersion_mm;
    y << YAML::Key << "feed_per_tooth_mm" << YAML::Value << spec.feed_per_tooth_mm;
    y << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    const std::string force_file = "truth/" + prefix + "-" + name + ".csv";
    write_force_file(ctx.out / force_file, cut, o.fs_hz);
    ++written;

    YAML::Node e(YAML::NodeType::Map);
    e["spindle_rpm"] = synth_number(rpm);
    e["teeth"] = o.force.teeth;
    e["force_file"] = force_file;
    e["window_s"] = synth_number_list({cut.harmonic_window_s[0], cut.harmonic_window_s[1]});
    e["noise_var_N2"] = synth_number_list({cut.noise_var_n2[0], cut.noise_var_n2[1]});
    YAML::Node ub(YAML::NodeType::Map);
    ub["x"] = unbalance_node(cut.unbalance_x);
    ub["y"] = unbalance_node(cut.unbalance_y);
    e["unbalance"] = ub;
    e["harmonics"] = harmonics_node(spec, cut, rpm);
    ctx.truth.tests[id] = e;
  }
  return written;
}

}  // namespace

std::shared_ptr<const KindSpec> parse_sifs_synth(const YAML::Node& section, const SynthContext& ctx,
                                                 YamlReader& r) {
  auto spec = std::make_shared<SifsSynthSpec>();
  if (!section.IsMap() && !section.IsNull()) {
    r.error("sifs", "must be a mapping (docs/format/synth-spec.md)");
    return spec;
  }
  const YAML::Node n = section.IsMap() ? section : YAML::Node(YAML::NodeType::Map);
  r.check_keys(n,
               {"folder", "calibration_matrix", "washer_scale_N_per_V", "plant", "filter_rate_hz",
                "static", "taps", "cuts"},
               "sifs");
  spec->folder = read_synth_folder(n, "sifs", spec->folder, r);
  read_matrix(n, r, spec->C);
  read(r, n, "washer_scale_N_per_V", "sifs", spec->washer_scale_N_per_V);
  positive(r, "sifs.washer_scale_N_per_V", spec->washer_scale_N_per_V);
  const YAML::Node plant = mapping(n, "plant", "sifs", r);
  r.check_keys(plant, {"x", "y"}, "sifs.plant");
  read_plant(plant["x"], "sifs.plant.x", r, spec->plant_x);
  read_plant(plant["y"], "sifs.plant.y", r, spec->plant_y);
  read(r, n, "filter_rate_hz", "sifs", spec->filter_rate_hz);
  positive(r, "sifs.filter_rate_hz", spec->filter_rate_hz);
  read_static(mapping(n, "static", "sifs", r), r, *spec);
  read_taps(mapping(n, "taps", "sifs", r), r, *spec);
  read_cuts(mapping(n, "cuts", "sifs", r), ctx, r, *spec);
  for (const auto* plant_modes : {&spec->plant_x, &spec->plant_y}) {
    for (const auto& m : *plant_modes) {
      if (m.fn_hz >= 0.45 * spec->tap.fs_hz || m.fn_hz >= 0.45 * spec->cut.fs_hz) {
        r.error("sifs.plant", "mode at " + synth_number(m.fn_hz) +
                                  " Hz: must be below 0.45 x the tap and cut sample rates");
      }
    }
  }
  return spec;
}

int write_sifs_synth(const KindSpec& section, SynthContext& ctx) {
  const auto& spec = dynamic_cast<const SifsSynthSpec&>(section);
  ctx.truth.top["calibration_matrix"] = matrix(spec.C);
  ctx.truth.top["sensitivity_matrix"] = matrix(spec.C.inverse());
  int written = write_static(spec, ctx);
  written += write_taps(spec, ctx);
  written += write_cuts(spec, ctx);
  return written;
}

}  // namespace chatterlab::app
