// The `spindle` section of a synth spec (docs/format/synth-spec.md): a spindle drive campaign of
// format section 5 made from the discrete drive of analysis/sysid/spindle_drive.h: a sweep-frf
// test <folder>/sweep (a logarithmic sine sweep on the speed command) and spindle-current tests
// <folder>/cut-n<rpm, 5 digits> (the nominal cut's torque on the spindle, the commanded
// current quantized, a dynamometer reference through its own resonance), with their truth
// (format section 5, "truth.yaml").
#include <cmath>
#include <cstdio>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

#include "analysis/common/constants.h"
#include "analysis/sysid/spindle_drive.h"
#include "analysis/sysid/torque_observer.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

namespace {

struct SpindleSynthSpec : KindSpec {
  std::string folder = "spindle";
  double fs_hz = 10000.0;
  double kt_nm_per_a = 0.8;
  double current_resolution_A = 0.01;
  double current_noise_A = 0.003;  // on the logged currents, before quantization
  double speed_noise_rpm = 0.2;
  // sweep
  double sweep_rpm = 5000.0;
  double band_lo_hz = 5.0, band_hi_hz = 3000.0;
  double sweep_s = 20.0;
  double sweep_amplitude_rpm = 20.0;
  int segment_samples = 4096;
  // cuts
  std::vector<double> rpm{3000.0, 5000.0, 7000.0};
  double axial_depth_mm = 2.0;
  double radial_immersion_mm = -1.0;  // < 0: slot (the tool diameter)
  double feed_per_tooth_mm = 0.1;
  bool up_milling = true;
  double Ktc_N_m2 = 7.976e8, Kte_N_m = 2.57e4;
  double cut_s = 1.6, engage_s = 0.4;
  double dyno_rate_hz = 25600.0, dyno_fn_hz = 1100.0, dyno_zeta = 0.2, dyno_noise_Nm = 0.01;
};

void read(YamlReader& r, const YAML::Node& n, const std::string& key, const std::string& path,
          double& v) {
  if (const auto x = r.optional_double(n, key, path)) v = *x;
}

void positive(YamlReader& r, const std::string& key, double v) {
  if (!(v > 0.0)) r.error(key, "must be > 0");
}

YAML::Node sub(const YAML::Node& n, const std::string& key, const std::string& path,
               YamlReader& r) {
  const YAML::Node s = n[key];
  if (!s) return YAML::Node(YAML::NodeType::Map);
  if (!s.IsMap()) {
    r.error(path + "." + key, "must be a mapping");
    return YAML::Node(YAML::NodeType::Map);
  }
  return s;
}

std::string cut_name(double rpm) {
  char b[32];
  std::snprintf(b, sizeof b, "cut-n%05lld", std::llround(rpm));
  return b;
}

// The dynamometer: a second-order low-pass of unit static gain (its resonance fn, zeta),
// discretized by zero-order hold at its rate.
Eigen::VectorXd dynamometer(const Eigen::VectorXd& torque, double fs, double fn, double zeta) {
  const double wn = kTwoPi * fn;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  M(0, 1) = 1.0;
  M(1, 0) = -wn * wn;
  M(1, 1) = -2.0 * zeta * wn;
  M(1, 2) = wn * wn;
  const Eigen::Matrix3d E = (M / fs).exp();
  const Eigen::Matrix2d Ad = E.topLeftCorner(2, 2);
  const Eigen::Vector2d Bd = E.topRightCorner(2, 1);
  Eigen::VectorXd out(torque.size());
  Eigen::Vector2d x(torque.size() > 0 ? torque[0] : 0.0, 0.0);
  for (Eigen::Index k = 0; k < torque.size(); ++k) {
    out[k] = x[0];
    x = Ad * x + Bd * torque[k];
  }
  return out;
}

// The drive of notes/001.md sec. 7.1 A at the spec's rate and torque constant (speed-loop
// crossover near 100 Hz whatever Kt), its current loop one controller sample late.
sysid::SpindleDriveParams drive_params(const SpindleSynthSpec& s) {
  sysid::SpindleDriveParams p;
  p.sample_rate_hz = s.fs_hz;
  p.kt_nm_per_a = s.kt_nm_per_a;
  p.kp_a_s_per_rad = (p.j1_kg_m2 + p.j2_kg_m2) * kTwoPi * 100.0 / s.kt_nm_per_a;
  p.current_delay_s = 1.0 / s.fs_hz;
  return p;
}

}  // namespace

std::shared_ptr<const KindSpec> SweepFrfKind::parse_synth(const YAML::Node& section,
                                                          const SynthContext& ctx,
                                                          YamlReader& r) const {
  auto s = std::make_shared<SpindleSynthSpec>();
  if (!section.IsMap() && !section.IsNull()) {
    r.error("spindle", "must be a mapping (docs/format/synth-spec.md)");
    return s;
  }
  const YAML::Node n = section.IsMap() ? section : YAML::Node(YAML::NodeType::Map);
  r.check_keys(n,
               {"folder", "sample_rate_hz", "torque_constant_Nm_per_A", "current_resolution_A",
                "current_noise_A", "speed_noise_rpm", "sweep", "cuts", "dynamometer"},
               "spindle");
  s->folder = read_synth_folder(n, "spindle", s->folder, r);
  read(r, n, "sample_rate_hz", "spindle", s->fs_hz);
  read(r, n, "torque_constant_Nm_per_A", "spindle", s->kt_nm_per_a);
  read(r, n, "current_resolution_A", "spindle", s->current_resolution_A);
  read(r, n, "speed_noise_rpm", "spindle", s->speed_noise_rpm);
  read(r, n, "current_noise_A", "spindle", s->current_noise_A);
  if (!(s->current_noise_A >= 0.0)) r.error("spindle.current_noise_A", "must be >= 0");
  positive(r, "spindle.sample_rate_hz", s->fs_hz);
  positive(r, "spindle.torque_constant_Nm_per_A", s->kt_nm_per_a);
  positive(r, "spindle.current_resolution_A", s->current_resolution_A);
  if (!(s->speed_noise_rpm >= 0.0)) r.error("spindle.speed_noise_rpm", "must be >= 0");
  const YAML::Node sw = sub(n, "sweep", "spindle", r);
  r.check_keys(sw, {"spindle_rpm", "band_hz", "duration_s", "amplitude_rpm", "segment_samples"},
               "spindle.sweep");
  read(r, sw, "spindle_rpm", "spindle.sweep", s->sweep_rpm);
  if (const auto b = r.optional_pair(sw, "band_hz", "spindle.sweep")) {
    std::tie(s->band_lo_hz, s->band_hi_hz) = *b;
  }
  if (!(s->band_lo_hz > 0.0 && s->band_hi_hz > s->band_lo_hz && s->band_hi_hz < 0.5 * s->fs_hz)) {
    r.error("spindle.sweep.band_hz", "must be [low, high] with 0 < low < high < rate / 2");
  }
  read(r, sw, "duration_s", "spindle.sweep", s->sweep_s);
  read(r, sw, "amplitude_rpm", "spindle.sweep", s->sweep_amplitude_rpm);
  if (const auto k = r.optional_int(sw, "segment_samples", "spindle.sweep", 64, 1 << 20)) {
    if (*k % 2 != 0) r.error("spindle.sweep.segment_samples", "must be even");
    s->segment_samples = static_cast<int>(*k);
  }
  positive(r, "spindle.sweep.spindle_rpm", s->sweep_rpm);
  positive(r, "spindle.sweep.amplitude_rpm", s->sweep_amplitude_rpm);
  if (!(s->sweep_s * s->fs_hz >= 2.0 * s->segment_samples)) {
    r.error("spindle.sweep.duration_s", "must hold at least two segments");
  }
  const YAML::Node cu = sub(n, "cuts", "spindle", r);
  r.check_keys(cu,
               {"rpm", "axial_depth_mm", "radial_immersion_mm", "feed_per_tooth_mm", "operation",
                "Ktc_N_m2", "Kte_N_m", "duration_s", "engage_s"},
               "spindle.cuts");
  if (cu["rpm"]) {
    s->rpm.clear();
    if (!cu["rpm"].IsSequence() || cu["rpm"].size() == 0) {
      r.error("spindle.cuts.rpm", "must be a list of speeds");
    } else {
      for (const auto& v : cu["rpm"]) {
        double x = 0.0;
        if (!v.IsScalar() || !YAML::convert<double>::decode(v, x) || !(x > 0.0)) {
          r.error("spindle.cuts.rpm", "every speed must be a number > 0");
        } else {
          s->rpm.push_back(x);
        }
      }
    }
  }
  read(r, cu, "axial_depth_mm", "spindle.cuts", s->axial_depth_mm);
  read(r, cu, "radial_immersion_mm", "spindle.cuts", s->radial_immersion_mm);
  read(r, cu, "feed_per_tooth_mm", "spindle.cuts", s->feed_per_tooth_mm);
  read(r, cu, "Ktc_N_m2", "spindle.cuts", s->Ktc_N_m2);
  read(r, cu, "Kte_N_m", "spindle.cuts", s->Kte_N_m);
  read(r, cu, "duration_s", "spindle.cuts", s->cut_s);
  read(r, cu, "engage_s", "spindle.cuts", s->engage_s);
  const std::string op = r.optional_string(cu, "operation", "spindle.cuts").value_or("up-milling");
  if (op != "up-milling" && op != "down-milling") {
    r.error("spindle.cuts.operation", "must be up-milling or down-milling");
  }
  s->up_milling = op == "up-milling";
  positive(r, "spindle.cuts.axial_depth_mm", s->axial_depth_mm);
  positive(r, "spindle.cuts.feed_per_tooth_mm", s->feed_per_tooth_mm);
  if (!(s->engage_s >= 0.35 && s->cut_s >= s->engage_s + 0.3)) {
    r.error("spindle.cuts", "needs engage_s >= 0.35 and duration_s >= engage_s + 0.3");
  }
  const YAML::Node dy = sub(n, "dynamometer", "spindle", r);
  r.check_keys(dy, {"sample_rate_hz", "fn_hz", "zeta", "noise_Nm"}, "spindle.dynamometer");
  read(r, dy, "sample_rate_hz", "spindle.dynamometer", s->dyno_rate_hz);
  read(r, dy, "fn_hz", "spindle.dynamometer", s->dyno_fn_hz);
  read(r, dy, "zeta", "spindle.dynamometer", s->dyno_zeta);
  read(r, dy, "noise_Nm", "spindle.dynamometer", s->dyno_noise_Nm);
  positive(r, "spindle.dynamometer.sample_rate_hz", s->dyno_rate_hz);
  positive(r, "spindle.dynamometer.fn_hz", s->dyno_fn_hz);
  positive(r, "spindle.dynamometer.zeta", s->dyno_zeta);
  if (!ctx.tool) r.error("tool", "is required by the spindle section (the cuts' tool)");
  if (s->fs_hz > 0.0 && s->kt_nm_per_a > 0.0) {
    try {
      const sysid::SpindleDrive check(drive_params(*s));
    } catch (const InputError& e) {
      r.error("spindle.sample_rate_hz",
              std::string("the drive cannot run at this rate: ") + e.what());
    }
  }
  return s;
}

int SweepFrfKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  const auto& s = dynamic_cast<const SpindleSynthSpec&>(section);
  const sysid::SpindleDrive drive(drive_params(s));
  const double fs = s.fs_hz;
  const double q = s.current_resolution_A;
  const auto quantize = [q](double v) { return std::round(v / q); };  // counts
  // ---- the sweep: a logarithmic sine sweep of the speed command, band_hz over duration_s.
  const std::string sweep_id = s.folder + "/sweep";
  {
    const Eigen::Index n = static_cast<Eigen::Index>(std::llround(s.sweep_s * fs));
    Eigen::VectorXd ref(n), tau = Eigen::VectorXd::Zero(n);
    // The chirp runs a little beyond the band the test states (half the low end, 15 % above
    // the high end, below 0.48 fs): Welch's segments at the sweep's ends see only part of it.
    const double T = s.sweep_s, f0 = 0.5 * s.band_lo_hz,
                 f1 = std::min(1.15 * s.band_hi_hz, 0.48 * fs);
    const double L = T / std::log(f1 / f0);
    for (Eigen::Index k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) / fs;
      ref[k] =
          s.sweep_rpm + s.sweep_amplitude_rpm * std::sin(kTwoPi * f0 * L * (std::exp(t / L) - 1.0));
    }
    const sysid::SpindleDriveRecord rec = drive.simulate(ref, tau);
    std::mt19937_64 rng(ctx.stream_seed("synth.spindle.sweep", 0));
    std::normal_distribution<double> nd(0.0, 1.0);
    Eigen::VectorXd speed(n), cur(n), act(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      speed[k] = rec.speed_rpm[k] + s.speed_noise_rpm * nd(rng);
      cur[k] = quantize(rec.current_nom_a[k] + s.current_noise_A * nd(rng));
      act[k] = quantize(rec.current_act_a[k] + s.current_noise_A * nd(rng));
    }
    const auto dir = ctx.out / sweep_id;
    std::filesystem::create_directories(dir);
    const std::vector<std::string> names = {"speed_ref", "speed", "current", "current_act"};
    write_signals(dir / "sweep.f32", names, {&ref, &speed, &cur, &act});
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "sweep-frf";
    y << YAML::Key << "sample_rate_hz" << YAML::Value << fs;
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "sweep.f32" << YAML::Key << "channels" << YAML::Value << YAML::Flow
      << YAML::BeginSeq;
    for (const auto& c : names) y << c;
    y << YAML::EndSeq << YAML::EndMap;
    y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
    for (const char* c : {"current", "current_act"}) {
      y << YAML::Key << c << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale"
        << YAML::Value << q << YAML::EndMap;
    }
    y << YAML::EndMap;
    y << YAML::Key << "spindle_rpm" << YAML::Value << s.sweep_rpm;
    y << YAML::Key << "sweep_band_hz" << YAML::Value << YAML::Flow << YAML::BeginSeq << s.band_lo_hz
      << s.band_hi_hz << YAML::EndSeq;
    y << YAML::Key << "torque_constant_Nm_per_A" << YAML::Value << s.kt_nm_per_a;
    y << YAML::Key << "segment_samples" << YAML::Value << s.segment_samples;
    y << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    // Truth: the noise-free torque-to-current FRF on a 1 Hz grid and the closed-loop modes.
    const Eigen::Index nf = static_cast<Eigen::Index>(0.5 * fs) + 1;
    const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(nf, 0.0, static_cast<double>(nf - 1));
    const Eigen::VectorXcd G = drive.torque_to_current(f);
    const std::string truth_csv = "truth/" + underscored(sweep_id) + ".csv";
    std::filesystem::create_directories((ctx.out / truth_csv).parent_path());
    const Eigen::VectorXd re = G.real(), im = G.imag();
    write_signals(ctx.out / truth_csv, {"freq_hz", "re", "im"}, {&f, &re, &im});
    const sysid::DiscreteStateSpace m = drive.torque_to_current_model();
    YAML::Node e(YAML::NodeType::Map);
    e["dc_gain_A_per_Nm"] = synth_number(drive.dc_gain_torque_to_current());
    e["sample_rate_hz"] = synth_number(fs);
    e["check_band_hz"] = synth_number_list({s.band_lo_hz, std::min(s.band_hi_hz, 2000.0)});
    e["frf_file"] = truth_csv;
    YAML::Node modes(YAML::NodeType::Sequence);
    for (const auto& md : sysid::modes_of(sysid::poles(m), fs)) {
      if (md.fn_hz < s.band_lo_hz || md.fn_hz > s.band_hi_hz) continue;
      YAML::Node mm(YAML::NodeType::Map);
      mm["fn_hz"] = synth_number(md.fn_hz);
      mm["zeta"] = synth_number(md.zeta);
      mm.SetStyle(YAML::EmitterStyle::Flow);
      modes.push_back(mm);
    }
    e["modes"] = modes;
    ctx.truth.tests[sweep_id] = e;
    YAML::Node top(YAML::NodeType::Map);
    top["torque_constant_Nm_per_A"] = synth_number(s.kt_nm_per_a);
    ctx.truth.top["spindle"] = top;
  }
  // ---- the cuts.
  const SynthTool& tool = *ctx.tool;
  const double immersion_mm =
      s.radial_immersion_mm > 0 ? s.radial_immersion_mm : 2.0 * tool.radius_mm;
  int written = 1;
  for (std::size_t i = 0; i < s.rpm.size(); ++i) {
    const double rpm = s.rpm[i];
    sysid::NominalCut c;
    c.spindle_rpm = rpm;
    c.teeth = tool.teeth;
    c.tool_radius_m = tool.radius_m();
    c.helix_deg = tool.helix_deg.value_or(0.0);
    c.axial_depth_m = s.axial_depth_mm * 1e-3;
    c.radial_immersion_m = immersion_mm * 1e-3;
    c.up_milling = s.up_milling;
    c.feed_per_tooth_m = s.feed_per_tooth_mm * 1e-3;
    c.Ktc_N_m2 = s.Ktc_N_m2;
    c.Kte_N_m = s.Kte_N_m;
    const Eigen::Index n = static_cast<Eigen::Index>(std::llround(s.cut_s * fs));
    const Eigen::Index k_in = static_cast<Eigen::Index>(std::llround(s.engage_s * fs));
    // The torque held over each sample: the mean of 4 sub-samples of the nominal torque.
    constexpr int kSub = 4;
    const Eigen::VectorXd fine = sysid::nominal_cutting_torque(c, kSub * fs, kSub * n);
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(n);
    for (Eigen::Index k = k_in; k < n; ++k) tau[k] = fine.segment(kSub * k, kSub).mean();
    const sysid::SpindleDriveRecord rec = drive.simulate(Eigen::VectorXd::Constant(n, rpm), tau);
    std::mt19937_64 rng(ctx.stream_seed("synth.spindle.cut", i));
    std::normal_distribution<double> nd(0.0, 1.0);
    Eigen::VectorXd cur(n), speed(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      cur[k] = quantize(rec.current_nom_a[k] + s.current_noise_A * nd(rng));
      speed[k] = rec.speed_rpm[k] + s.speed_noise_rpm * nd(rng);
    }
    const std::string id = s.folder + "/" + cut_name(rpm);
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    write_signals(dir / "current.f32", {"current", "speed"}, {&cur, &speed});
    // The dynamometer at its own rate: the nominal torque through its resonance, plus noise.
    const Eigen::Index nd_s = static_cast<Eigen::Index>(std::llround(s.cut_s * s.dyno_rate_hz));
    Eigen::VectorXd dt = sysid::nominal_cutting_torque(c, s.dyno_rate_hz, nd_s);
    const Eigen::Index kd_in = static_cast<Eigen::Index>(std::llround(s.engage_s * s.dyno_rate_hz));
    dt.head(kd_in).setZero();
    Eigen::VectorXd dyn = dynamometer(dt, s.dyno_rate_hz, s.dyno_fn_hz, s.dyno_zeta);
    Eigen::VectorXd tcol(nd_s);
    for (Eigen::Index k = 0; k < nd_s; ++k) {
      dyn[k] += s.dyno_noise_Nm * nd(rng);
      tcol[k] = static_cast<double>(k) / s.dyno_rate_hz;
    }
    write_signals(dir / "dyno.csv", {"t", "torque"}, {&tcol, &dyn});
    const double air0 = 0.02, air1 = s.engage_s - 0.1;
    const double cut0 = s.engage_s + 0.1, cut1 = s.cut_s - 0.05;
    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "spindle-current";
    y << YAML::Key << "sample_rate_hz" << YAML::Value << fs;
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "current.f32" << YAML::Key << "channels" << YAML::Value << YAML::Flow
      << YAML::BeginSeq << "current"
      << "speed" << YAML::EndSeq << YAML::EndMap;
    y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap << YAML::Key << "current"
      << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "scale" << YAML::Value << q
      << YAML::EndMap << YAML::EndMap;
    y << YAML::Key << "current_resolution_A" << YAML::Value << q;
    y << YAML::Key << "model" << YAML::Value << sweep_id;
    y << YAML::Key << "spindle_rpm" << YAML::Value << rpm;
    y << YAML::Key << "operation" << YAML::Value << (s.up_milling ? "up-milling" : "down-milling");
    y << YAML::Key << "radial_immersion_mm" << YAML::Value << immersion_mm;
    y << YAML::Key << "axial_depth_mm" << YAML::Value << s.axial_depth_mm;
    y << YAML::Key << "feed_per_tooth_mm" << YAML::Value << s.feed_per_tooth_mm;
    y << YAML::Key << "Ktc_N_m2" << YAML::Value << s.Ktc_N_m2;
    y << YAML::Key << "Kte_N_m" << YAML::Value << s.Kte_N_m;
    y << YAML::Key << "air_window_s" << YAML::Value << YAML::Flow << YAML::BeginSeq << air0 << air1
      << YAML::EndSeq;
    y << YAML::Key << "cut_window_s" << YAML::Value << YAML::Flow << YAML::BeginSeq << cut0 << cut1
      << YAML::EndSeq;
    y << YAML::Key << "dynamometer" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "file" << YAML::Value << "dyno.csv" << YAML::Key << "sample_rate_hz" << YAML::Value
      << s.dyno_rate_hz << YAML::EndMap;
    y << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);
    // Truth: the torque held over each sample, at the sample interval's centre.
    Eigen::VectorXd t(n);
    for (Eigen::Index k = 0; k < n; ++k) t[k] = (static_cast<double>(k) + 0.5) / fs;
    const std::string torque_csv = "truth/" + underscored(id) + "_torque.csv";
    write_signals(ctx.out / torque_csv, {"t", "torque"}, {&t, &tau});
    YAML::Node e(YAML::NodeType::Map);
    e["torque_file"] = torque_csv;
    e["model"] = sweep_id;
    e["sample_rate_hz"] = synth_number(fs);
    e["cut_window_s"] = synth_number_list({cut0, cut1});
    e["air_window_s"] = synth_number_list({air0, air1});
    e["Q_Nm2"] = synth_number(sysid::torque_increment_variance(c, fs));
    e["R_A2"] = synth_number(q * q / 12.0);
    e["tooth_pass_hz"] = synth_number(tool.teeth * rpm / 60.0);
    e["dynamometer_file"] = id + "/dyno.csv";
    e["torque_mean_Nm"] = synth_number(tau.segment(static_cast<Eigen::Index>(cut0 * fs),
                                                   static_cast<Eigen::Index>((cut1 - cut0) * fs))
                                           .mean());
    ctx.truth.tests[id] = e;
    ++written;
  }
  return written;
}

}  // namespace chatterlab::app
