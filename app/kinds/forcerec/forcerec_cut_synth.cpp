// The `cuts:` block of the synth section `forcerec` (docs/format/synth-spec.md): force-record
// tests, cut records measured through the table dynamometer, with their truth.yaml entries
// (EXPERIMENT_FORMAT section 4, "kind: force-record" and "truth.yaml (synthetic forcerec
// campaigns)").
//
// Force (on the workpiece, N, along the dynamometer's x and y). A rigid tool (no vibration,
// zero helix) of the spec's teeth and radius turns at spindle_rpm from t = 0, theta_1 = 2 pi
// rpm / 60 t; tooth p at theta_p (milling/force_model.h: from +y towards +x) cuts inside the
// engagement window of the operation and radial immersion (milling/engagement.h; down-milling
// with the workpiece on -y, up-milling on +y, feed along +x) with the chip
//   h_p = f_t sin(theta_p) + rho_p - rho_(p-1)      (rho_1 = runout, rho_p = 0 otherwise;
//                                                   p - 1 cyclic: tooth 1 follows tooth n)
// and F_t = Ktc a h + Kte a, F_r = Krc a h + Kre a (zero where h <= 0). tooth_force_xy_N gives
// the force on the TOOL (000 eqs 2.3-2.4: F_t against the cutting velocity, F_r towards the
// axis); the workpiece gets its negative. The tool is not engaged before air_s; the engagement
// then ramps over kRampS as (1 - cos(pi u / kRampS)) / 2 (a factor on the whole force) and
// stays 1 to the end. With runout the force repeats per spindle revolution, not per tooth.
//
// Measurement. The force is evaluated at 16 x sample_rate_hz (each fine step holds it at its
// mid-point) and drives 004 Table 3.1's x and y models discretized there (zero-order hold), so
// that no method sees its own discretization; y(k) = C x at t = k / fs (the force of interval
// k first shows in y(k+1)), plus white Gaussian noise of std noise_N per axis, written in volts
// (raw = (N - offset) / scale) to forces.f32 [Fx, Fy]. Both axes are always simulated (the
// format requires Fx and Fy); frf_tests and the truth's axes hold the axes of forcerec.axes
// among x and y (z is not written for cuts). reference.f32 [Fx, Fy]: per sample k the mean of
// the 16 fine mid-point forces of [k/fs, (k+1)/fs), raw floats without calibration.
//
// Truth (format section 4). The figures come from analysis/forcerec/force_metrics.h over the
// values the files hold (float32 rounded, as the kind reads them). Oracles with the true model
// discretized at fs: the plain one-step ZOH inverse of the measured output (smo.h), and the
// smallest NRMSE of deconvolve_tikhonov_at over the alpha grid 1e-8..1e2, 10 per decade.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "analysis/common/check.h"
#include "analysis/common/constants.h"
#include "analysis/forcerec/deconvolution.h"
#include "analysis/forcerec/force_metrics.h"
#include "analysis/forcerec/model.h"
#include "analysis/forcerec/smo.h"
#include "analysis/forcerec/transfer_fit.h"
#include "analysis/milling/engagement.h"
#include "analysis/milling/force_model.h"
#include "app/core/signals.h"
#include "app/kinds/forcerec/forcerec_synth.h"

namespace chatterlab::app::forcerec_synth {
namespace {

constexpr double kRampS = 0.02;            // engagement ramp after air_s
constexpr double kAirGuardS = 0.05;        // air_window_s = [0, air_s - kAirGuardS]
constexpr double kCutStartS = 0.1;         // cut_window_s begins kCutStartS after air_s
constexpr double kCutEndGuardS = 0.05;     // and ends kCutEndGuardS before the record's end
constexpr double kMaxSamples = 2e7;        // duration_s x sample_rate_hz
constexpr std::size_t kMaxCuts = 20;       // entries of cuts.list
constexpr double kMaxToothFraction = 0.4;  // f_tp < 0.4 fs
// Calibration written to test.yaml `channels` (raw = (N - offset) / scale).
struct ChannelCalibration {
  const char* name;
  char axis;
  double scale_N_per_V, offset_N;
};
constexpr std::array<ChannelCalibration, 2> kChannels = {
    {{"Fx", 'x', 50.0, -2.2}, {"Fy", 'y', 50.0, 0.4}}};

const std::string kPath = "forcerec.cuts";

double rounded_to_float(double v) { return static_cast<double>(static_cast<float>(v)); }

bool plain_folder_name(const std::string& name) {
  static const std::regex kPlain("[A-Za-z0-9_][A-Za-z0-9._-]*");
  return std::regex_match(name, kPlain);
}

void parse_cut_entry(const YAML::Node& e, std::size_t i, const CutsSpec& c, YamlReader& r,
                     std::set<std::string>& names, CutSpec& cut) {
  const std::string path = kPath + ".list[" + std::to_string(i) + "]";
  if (!e.IsMap()) {
    r.error(path,
            "must be a mapping {name, spindle_rpm, operation, axial_depth_mm, "
            "radial_immersion_mm, feed_per_tooth_mm}");
    return;
  }
  r.check_keys(e,
               {"name", "spindle_rpm", "operation", "axial_depth_mm", "radial_immersion_mm",
                "feed_per_tooth_mm"},
               path);
  cut.name = r.required_string(e, "name", path);
  if (!e["name"]) {
    // reported as missing
  } else if (!plain_folder_name(cut.name)) {
    r.error(path + ".name", "'" + cut.name +
                                "' must be a plain folder name (letters, digits, '.', '_', '-', "
                                "not starting with '.' or '-')");
  } else if (!names.insert(cut.name).second) {
    r.error(path + ".name", "'" + cut.name + "' is used by another cut");
  }
  const std::string op = r.required_string(e, "operation", path);
  if (op == "down-milling") {
    cut.operation = milling::Operation::kDownMilling;
  } else if (op == "up-milling") {
    cut.operation = milling::Operation::kUpMilling;
  } else if (e["operation"]) {
    r.error(path + ".operation", "must be up-milling or down-milling, not '" + op + "'");
  }
  cut.spindle_rpm = r.required_double(e, "spindle_rpm", path);
  cut.axial_depth_mm = r.required_double(e, "axial_depth_mm", path);
  cut.radial_immersion_mm = r.required_double(e, "radial_immersion_mm", path);
  cut.feed_per_tooth_mm = r.required_double(e, "feed_per_tooth_mm", path);
  for (const auto& [key, v] : {std::pair<const char*, double>{"spindle_rpm", cut.spindle_rpm},
                               {"axial_depth_mm", cut.axial_depth_mm},
                               {"radial_immersion_mm", cut.radial_immersion_mm},
                               {"feed_per_tooth_mm", cut.feed_per_tooth_mm}}) {
    if (e[key] && !(v > 0.0)) r.error(path + "." + key, "must be > 0");
  }
  if (c.teeth > 0 && cut.spindle_rpm > 0.0 &&
      !(cut.spindle_rpm * c.teeth / 60.0 < kMaxToothFraction * c.fs_hz)) {
    r.error(path + ".spindle_rpm", "gives a tooth frequency spindle_rpm x teeth / 60 = " +
                                       synth_number(cut.spindle_rpm * c.teeth / 60.0) +
                                       " Hz: must be below 0.4 x forcerec.cuts.sample_rate_hz");
  }
  if (c.radius_m > 0.0 && cut.radial_immersion_mm > 2e3 * c.radius_m) {
    r.error(path + ".radial_immersion_mm",
            "must be at most the tool's diameter (" + synth_number(2e3 * c.radius_m) + " mm)");
  }
}

void parse_coefficients(const YAML::Node& n, CutsSpec& c, YamlReader& r) {
  const std::string path = kPath + ".coefficients";
  if (!n.IsMap()) {
    r.error(path, "must be a mapping {Ktc_N_m2, Krc_N_m2, Kte_N_m, Kre_N_m}");
    return;
  }
  r.check_keys(n, {"Ktc_N_m2", "Krc_N_m2", "Kte_N_m", "Kre_N_m"}, path);
  const auto read_nonnegative = [&](const char* key, double& out) {
    out = r.optional_double(n, key, path).value_or(out);
    if (!(out >= 0.0)) r.error(path + "." + key, "must be >= 0");
  };
  read_nonnegative("Ktc_N_m2", c.coefficients.Kt_N_m2);
  read_nonnegative("Krc_N_m2", c.coefficients.Kr_N_m2);
  read_nonnegative("Kte_N_m", c.coefficients.Kte_N_m);
  read_nonnegative("Kre_N_m", c.coefficients.Kre_N_m);
  if (!(c.coefficients.Kt_N_m2 > 0.0)) r.error(path + ".Ktc_N_m2", "must be > 0");
}

double engagement_at(const CutsSpec& c, double t_s) {
  const double u = t_s - c.air_s;
  if (u < 0.0) return 0.0;
  if (u >= kRampS) return 1.0;
  return 0.5 * (1.0 - std::cos(kPi * u / kRampS));
}

// One cut's simulated records (N, before calibration and float rounding).
struct CutRecords {
  Eigen::VectorXd reference[2];  // x, y: interval means
  Eigen::VectorXd output[2];     // x, y: noise-free dynamometer output y(k) = C x(k)
};

CutRecords simulate_cut(const CutsSpec& c, const CutSpec& cut) {
  const Eigen::Index n = static_cast<Eigen::Index>(std::llround(c.duration_s * c.fs_hz));
  CutRecords rec;
  forcerec::DiscreteModel fine[2];
  Eigen::VectorXd x[2];
  for (int a = 0; a < 2; ++a) {
    fine[a] =
        oversampled_model(table31_model(kChannels[static_cast<std::size_t>(a)].axis), c.fs_hz);
    x[a] = Eigen::VectorXd::Zero(fine[a].order());
    rec.reference[a].resize(n);
    rec.output[a].resize(n);
  }
  const double dt = 1.0 / (c.fs_hz * kOversampling);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int a = 0; a < 2; ++a) rec.output[a][k] = fine[a].C.dot(x[a]);
    for (int j = 0; j < kOversampling; ++j) {
      const double t = (static_cast<double>(k * kOversampling + j) + 0.5) * dt;
      const Eigen::Vector2d f = cut_force_on_workpiece_N(c, cut, t, engagement_at(c, t));
      sum += f;
      for (int a = 0; a < 2; ++a) x[a] = fine[a].Ad * x[a] + fine[a].Bd * f[a];
    }
    for (int a = 0; a < 2; ++a) rec.reference[a][k] = sum[a] / kOversampling;
  }
  return rec;
}

double rms_over(const Eigen::VectorXd& v, const forcerec::IndexWindow& w) {
  return std::sqrt(v.segment(w.begin, w.size()).squaredNorm() / static_cast<double>(w.size()));
}

// The truth entry of one axis (format section 4).
YAML::Node axis_truth(const CutsSpec& c, const std::string& frf_test, char axis,
                      const Eigen::VectorXd& reference, const Eigen::VectorXd& measured,
                      double tooth_freq_hz, double cut_begin_s, double cut_end_s) {
  const Eigen::Index n = reference.size();
  const forcerec::IndexWindow eval = forcerec::evaluation_window(n, c.fs_hz);
  const forcerec::IndexWindow hw =
      forcerec::harmonic_window(n, c.fs_hz, tooth_freq_hz, cut_begin_s, cut_end_s);
  const int count = forcerec::harmonic_count(c.fs_hz, tooth_freq_hz);
  CHATTERLAB_CHECK(eval.size() > 0 && hw.size() > 0,
                   "parse_cuts keeps the evaluation and harmonic windows non-empty");
  const forcerec::Harmonics ref_h =
      forcerec::tooth_harmonics(reference, hw, c.fs_hz, tooth_freq_hz, count);
  const forcerec::Harmonics meas_h =
      forcerec::tooth_harmonics(measured, hw, c.fs_hz, tooth_freq_hz, count);

  const forcerec::DiscreteModel model =
      forcerec::zoh(forcerec::realize_scaled_modal(table31_model(axis)), c.fs_hz);
  const forcerec::OneStepInverse inverse = forcerec::one_step_inverse(model);
  Eigen::VectorXd inverted(n);
  forcerec::run_one_step_inverse(inverse, measured, inverted);
  const double inverse_nrmse = forcerec::nrmse_pct(inverted, reference, eval);

  const forcerec::DeconvolutionOptions grid;  // 1e-8..1e2, 10 per decade
  const int steps = static_cast<int>(
      std::lround(std::log10(grid.alpha_max / grid.alpha_min) * grid.alphas_per_decade));
  double tikhonov_nrmse = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= steps; ++i) {
    const double alpha =
        grid.alpha_min * std::pow(10.0, static_cast<double>(i) / grid.alphas_per_decade);
    const forcerec::DeconvolutionResult d =
        forcerec::deconvolve_tikhonov_at(model, measured, alpha, grid);
    if (!d.summary.ok()) continue;
    tikhonov_nrmse = std::min(tikhonov_nrmse, forcerec::nrmse_pct(d.force_N, reference, eval));
  }
  CHATTERLAB_CHECK(std::isfinite(tikhonov_nrmse), "the Tikhonov oracle solved no grid alpha");

  YAML::Node e(YAML::NodeType::Map);
  e["frf_test"] = frf_test;
  e["noise_var_N2"] = synth_number(c.noise_N * c.noise_N);
  e["force_rms_N"] = synth_number(rms_over(reference, eval));
  e["mean_N"] = synth_number(ref_h.mean_N);
  e["harmonics_N"] = synth_number_list(ref_h.amplitudes_N);
  e["measured_harmonics_N"] = synth_number_list(meas_h.amplitudes_N);
  e["measured_nrmse_pct"] = synth_number(forcerec::nrmse_pct(measured, reference, eval));
  e["oracle_inverse_nrmse_pct"] = synth_number(inverse_nrmse);
  e["oracle_tikhonov_nrmse_pct"] = synth_number(tikhonov_nrmse);
  e.SetStyle(YAML::EmitterStyle::Block);
  return e;
}

YAML::Node flow_list(const std::vector<std::string>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const auto& s : v) n.push_back(s);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

}  // namespace

void parse_cuts(const YAML::Node& n, const SynthContext& ctx, ForcerecSynthSpec& s, YamlReader& r) {
  CutsSpec c;
  if (!n.IsMap()) {
    r.error(kPath, "must be a mapping (docs/format/synth-spec.md, section forcerec)");
    return;
  }
  r.check_keys(n,
               {"sample_rate_hz", "duration_s", "air_s", "noise_N", "coefficients", "runout_um",
                "drift", "list"},
               kPath);
  if (ctx.tool) {
    c.teeth = ctx.tool->teeth;
    c.radius_m = ctx.tool->radius_m();
  } else if (!ctx.tool_given) {
    r.error(kPath, "needs the spec's `tool` (teeth, radius_mm): the cuts' tool");
  }
  if (std::none_of(s.axes.begin(), s.axes.end(), [](char a) { return a == 'x' || a == 'y'; })) {
    r.error(kPath, "needs x or y in forcerec.axes (the cuts are reconstructed on x and y)");
  }
  const auto read = [&](const char* key, double& out) {
    out = r.optional_double(n, key, kPath).value_or(out);
  };
  read("sample_rate_hz", c.fs_hz);
  read("duration_s", c.duration_s);
  read("air_s", c.air_s);
  read("noise_N", c.noise_N);
  read("runout_um", c.runout_um);
  for (const auto& [key, v] :
       {std::pair<const char*, double>{"sample_rate_hz", c.fs_hz}, {"duration_s", c.duration_s}}) {
    if (!(v > 0.0)) r.error(kPath + "." + key, "must be > 0");
  }
  if (c.fs_hz > 0.0 && c.duration_s > 0.0 && !(c.fs_hz * c.duration_s <= kMaxSamples)) {
    r.error(kPath + ".duration_s", "x sample_rate_hz must be at most 2e7 samples");
  }
  if (!(c.air_s >= 2.0 * kAirGuardS && c.air_s < c.duration_s - 0.5)) {
    r.error(kPath + ".air_s", "must be >= 0.1 s and below duration_s - 0.5 s");
  }
  if (!(c.noise_N >= 0.0)) r.error(kPath + ".noise_N", "must be >= 0");
  if (!(c.runout_um >= 0.0 && c.runout_um <= 100.0)) {
    r.error(kPath + ".runout_um", "must be in [0, 100]");
  }
  if (const YAML::Node k = n["coefficients"]) parse_coefficients(k, c, r);
  if (const YAML::Node d = n["drift"]) {
    const std::string path = kPath + ".drift";
    if (!d.IsMap()) {
      r.error(path, "must be a mapping {fn_scale}");
    } else {
      r.check_keys(d, {"fn_scale"}, path);
      const double scale = r.required_double(d, "fn_scale", path);
      if (d["fn_scale"] && !(scale >= 0.5 && scale <= 2.0)) {
        r.error(path + ".fn_scale", "must be in [0.5, 2]");
      }
      c.drift_fn_scale = scale;
    }
  }
  const YAML::Node list = n["list"];
  if (!list) {
    r.error(kPath + ".list", "is missing: one entry per cut");
  } else if (!list.IsSequence() || list.size() == 0 || list.size() > kMaxCuts) {
    r.error(kPath + ".list", "must be a list of 1 to 20 cuts");
  } else {
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      CutSpec cut;
      parse_cut_entry(list[i], i, c, r, names, cut);
      c.list.push_back(cut);
    }
  }
  s.cuts = c;
}

Eigen::Vector2d cut_force_on_workpiece_N(const CutsSpec& cuts, const CutSpec& cut, double t_s,
                                         double engagement) {
  if (!(engagement > 0.0)) return Eigen::Vector2d::Zero();
  const milling::EngagementWindow window =
      milling::engagement_window(cut.operation, cuts.radius_m, cut.radial_immersion_mm * 1e-3);
  const double theta1 = kTwoPi * cut.spindle_rpm / 60.0 * t_s;
  const double feed_m = cut.feed_per_tooth_mm * 1e-3;
  const double depth_m = cut.axial_depth_mm * 1e-3;
  const double runout_m = cuts.runout_um * 1e-6;
  Eigen::Vector2d on_tool = Eigen::Vector2d::Zero();
  for (int p = 1; p <= cuts.teeth; ++p) {
    const double theta = milling::tooth_angle_rad(theta1, p, cuts.teeth);
    // Tooth 1 stands out by the runout: it cuts more, the tooth after it less.
    const auto radius_offset_m = [runout_m](int q) { return q == 1 ? runout_m : 0.0; };
    const int previous = p == 1 ? cuts.teeth : p - 1;
    const double runout_chip = radius_offset_m(p) - radius_offset_m(previous);
    const double h = milling::static_chip_thickness_m(feed_m, theta) + runout_chip;
    const bool engaged = milling::in_cut(theta, window.entry_rad, window.exit_rad);
    on_tool += milling::tooth_force_xy_N(
        milling::tooth_force(cuts.coefficients, h, depth_m, engaged), theta);
  }
  return -engagement * on_tool;
}

int write_cuts(const ForcerecSynthSpec& s, SynthContext& ctx) {
  CHATTERLAB_CHECK(s.cuts.has_value(), "write_cuts needs the cuts block");
  const CutsSpec& c = *s.cuts;
  int written = 0;
  for (std::size_t index = 0; index < c.list.size(); ++index) {
    const CutSpec& cut = c.list[index];
    const CutRecords rec = simulate_cut(c, cut);
    const Eigen::Index n = rec.reference[0].size();
    std::mt19937_64 rng(ctx.stream_seed("synth.forcerec.cut", index));
    std::normal_distribution<double> unit(0.0, 1.0);
    // Volts for the file; N and reference as the file holds them (float32) for the truth.
    Eigen::VectorXd volts[2], measured[2], reference[2];
    for (int a = 0; a < 2; ++a) {
      volts[a].resize(n);
      measured[a].resize(n);
      reference[a] = rec.reference[a].unaryExpr(&rounded_to_float);
    }
    for (Eigen::Index k = 0; k < n; ++k) {
      for (int a = 0; a < 2; ++a) {
        const ChannelCalibration& ch = kChannels[static_cast<std::size_t>(a)];
        const double y = rec.output[a][k] + c.noise_N * unit(rng);
        volts[a][k] = rounded_to_float((y - ch.offset_N) / ch.scale_N_per_V);
        measured[a][k] = volts[a][k] * ch.scale_N_per_V + ch.offset_N;
      }
    }
    const std::string id = s.folder + "/cuts/" + cut.name;
    const auto dir = ctx.out / id;
    std::filesystem::create_directories(dir);
    write_signals(dir / "forces.f32", {"Fx", "Fy"}, {&volts[0], &volts[1]});
    write_signals(dir / "reference.f32", {"Fx", "Fy"}, {&reference[0], &reference[1]});

    const double tooth_freq_hz = cut.spindle_rpm * c.teeth / 60.0;
    const double cut_begin_s = c.air_s + kCutStartS;
    const double cut_end_s = c.duration_s - kCutEndGuardS;
    YAML::Node frf_tests(YAML::NodeType::Map);
    for (char axis : s.axes) {
      if (axis == 'x' || axis == 'y') {
        frf_tests[std::string(1, axis)] = s.folder + "/hammer/" + std::string(1, axis);
      }
    }
    frf_tests.SetStyle(YAML::EmitterStyle::Flow);

    YAML::Emitter y;
    configure_synth_emitter(y);
    y << YAML::BeginMap << YAML::Key << "kind" << YAML::Value << "force-record";
    y << YAML::Key << "operation" << YAML::Value
      << (cut.operation == milling::Operation::kDownMilling ? "down-milling" : "up-milling");
    y << YAML::Key << "spindle_rpm" << YAML::Value << synth_number(cut.spindle_rpm);
    y << YAML::Key << "feed_per_tooth_mm" << YAML::Value << synth_number(cut.feed_per_tooth_mm);
    y << YAML::Key << "axial_depth_mm" << YAML::Value << synth_number(cut.axial_depth_mm);
    y << YAML::Key << "radial_immersion_mm" << YAML::Value << synth_number(cut.radial_immersion_mm);
    y << YAML::Key << "sample_rate_hz" << YAML::Value << synth_number(c.fs_hz);
    y << YAML::Key << "data" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "file"
      << YAML::Value << "forces.f32" << YAML::Key << "channels" << YAML::Value
      << flow_list({"Fx", "Fy"}) << YAML::EndMap;
    y << YAML::Key << "channels" << YAML::Value << YAML::BeginMap;
    for (const ChannelCalibration& ch : kChannels) {
      y << YAML::Key << ch.name << YAML::Value
        << synth_numbers({{"scale", ch.scale_N_per_V}, {"offset", ch.offset_N}});
    }
    y << YAML::EndMap;
    y << YAML::Key << "air_window_s" << YAML::Value
      << synth_number_list({0.0, c.air_s - kAirGuardS});
    y << YAML::Key << "cut_window_s" << YAML::Value << synth_number_list({cut_begin_s, cut_end_s});
    y << YAML::Key << "frf_tests" << YAML::Value << frf_tests;
    y << YAML::Key << "reference" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
      << "force" << YAML::Value << YAML::BeginMap << YAML::Key << "file" << YAML::Value
      << "reference.f32" << YAML::Key << "channels" << YAML::Value << flow_list({"Fx", "Fy"})
      << YAML::EndMap << YAML::EndMap;
    y << YAML::EndMap;
    write_synth_yaml(dir / "test.yaml", y);

    YAML::Node e(YAML::NodeType::Map);
    e["samples"] = static_cast<long long>(n);
    e["sample_rate_hz"] = synth_number(c.fs_hz);
    e["tooth_freq_hz"] = synth_number(tooth_freq_hz);
    e["harmonic_count"] = forcerec::harmonic_count(c.fs_hz, tooth_freq_hz);
    e["cut_window_s"] = synth_number_list({cut_begin_s, cut_end_s});
    e["force_file"] = id + "/reference.f32";
    e["channels"] = flow_list({"Fx", "Fy"});
    YAML::Node axes(YAML::NodeType::Map);
    for (int a = 0; a < 2; ++a) {
      const char axis = kChannels[static_cast<std::size_t>(a)].axis;
      if (std::find(s.axes.begin(), s.axes.end(), axis) == s.axes.end()) continue;
      axes[std::string(1, axis)] =
          axis_truth(c, s.folder + "/hammer/" + std::string(1, axis), axis, reference[a],
                     measured[a], tooth_freq_hz, cut_begin_s, cut_end_s);
    }
    e["axes"] = axes;
    ctx.truth.tests[id] = e;
    ++written;
  }
  return written;
}

}  // namespace chatterlab::app::forcerec_synth
