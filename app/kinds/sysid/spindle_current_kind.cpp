// Kind `spindle-current` (format section 5): cutting torque from the spindle's commanded
// current with the steady-state Kalman observer of 001 ch. 4 on a frf or sweep-frf model.
// See sysid_kinds.h and docs/sysid.md.
#include <chrono>
#include <cmath>
#include <complex>
#include <optional>

#include "analysis/common/constants.h"
#include "analysis/signal/resample.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/core/input_boundary.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/sysid/sysid_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

std::optional<std::pair<double, double>> read_window(const YAML::Node& root, YamlReader& r,
                                                     const std::string& key) {
  const auto w = r.optional_pair(root, key);
  if (!w) {
    if (!root[key]) r.error(key, "is required: [start_s, end_s]");
    return std::nullopt;
  }
  if (!(w->first >= 0.0 && w->second > w->first)) {
    r.error(key, "must be [start_s, end_s] with 0 <= start_s < end_s");
    return std::nullopt;
  }
  return w;
}

Eigen::Index sample_at(double t_s, double fs, Eigen::Index n) {
  return std::clamp<Eigen::Index>(static_cast<Eigen::Index>(std::llround(t_s * fs)), 0, n);
}

}  // namespace

std::string spindle_torque_path(const std::string& test_id) {
  return "torque/" + underscored(test_id.empty() ? std::string("root") : test_id) + ".csv";
}

std::vector<std::string> SpindleCurrentKind::keys() const {
  return {"current_resolution_A",
          "model",
          "spindle_rpm",
          "operation",
          "radial_immersion_mm",
          "axial_depth_mm",
          "feed_per_tooth_mm",
          "Ktc_N_m2",
          "Kte_N_m",
          "air_window_s",
          "cut_window_s",
          "dynamometer",
          "Q_Nm2",
          "R_A2"};
}

std::shared_ptr<const KindSpec> SpindleCurrentKind::parse(const YAML::Node& root,
                                                          YamlReader& r) const {
  auto s = std::make_shared<SpindleCurrentSpec>();
  s->current_resolution_A = r.required_double(root, "current_resolution_A");
  if (!(s->current_resolution_A > 0.0) && !std::isnan(s->current_resolution_A)) {
    r.error("current_resolution_A", "must be > 0");
  }
  s->model = r.required_string(root, "model");
  double feed = 0.0;
  read_speed_and_feed(root, r, &s->spindle_rpm, &feed);
  s->feed_per_tooth_m = feed;
  const std::string op = r.required_string(root, "operation");
  if (!op.empty() && op != "up-milling" && op != "down-milling") {
    r.error("operation", "must be up-milling or down-milling, got '" + op + "'");
  }
  s->up_milling = op != "down-milling";
  s->radial_immersion_m = r.required_double(root, "radial_immersion_mm") * kMm;
  if (!(s->radial_immersion_m > 0.0) && !std::isnan(s->radial_immersion_m)) {
    r.error("radial_immersion_mm", "must be > 0");
  }
  s->axial_depth_m = r.required_double(root, "axial_depth_mm") * kMm;
  if (!(s->axial_depth_m > 0.0) && !std::isnan(s->axial_depth_m)) {
    r.error("axial_depth_mm", "must be > 0");
  }
  s->Ktc_N_m2 = r.required_double(root, "Ktc_N_m2");
  s->Kte_N_m = r.required_double(root, "Kte_N_m");
  if (!(s->Ktc_N_m2 >= 0.0) && !std::isnan(s->Ktc_N_m2)) r.error("Ktc_N_m2", "must be >= 0");
  if (!(s->Kte_N_m >= 0.0) && !std::isnan(s->Kte_N_m)) r.error("Kte_N_m", "must be >= 0");
  const auto air = read_window(root, r, "air_window_s");
  const auto cut = read_window(root, r, "cut_window_s");
  if (air) std::tie(s->air_lo_s, s->air_hi_s) = *air;
  if (cut) std::tie(s->cut_lo_s, s->cut_hi_s) = *cut;
  if (air && cut && air->second > cut->first && air->first < cut->second) {
    r.error("air_window_s", "overlaps cut_window_s: the air window is spinning, not cutting");
  }
  if (const YAML::Node d = root["dynamometer"]) {
    if (!d.IsMap()) {
      r.error("dynamometer", "must be {file: dyno.csv, sample_rate_hz: 25600}");
    } else {
      r.check_keys(d, {"file", "sample_rate_hz"}, "dynamometer");
      s->dyno_file = r.required_string(d, "file", "dynamometer");
      s->dyno_rate_hz = r.required_double(d, "sample_rate_hz", "dynamometer");
      if (!(s->dyno_rate_hz > 0.0) && !std::isnan(s->dyno_rate_hz)) {
        r.error("dynamometer.sample_rate_hz", "must be > 0");
      }
      if (!s->dyno_file.empty() && !is_text_signal_file(s->dyno_file)) {
        r.error("dynamometer.file", "'" + s->dyno_file + "': must be a text (CSV) file");
      }
    }
  }
  if (const auto q = r.optional_double(root, "Q_Nm2")) {
    if (!(*q > 0.0)) r.error("Q_Nm2", "must be > 0");
    s->Q_Nm2 = q;
  }
  if (const auto v = r.optional_double(root, "R_A2")) {
    if (!(*v > 0.0)) r.error("R_A2", "must be > 0");
    s->R_A2 = v;
  }
  return s;
}

std::vector<std::string> SpindleCurrentKind::check_campaign(const CampaignSpec& c,
                                                            const TestSpec& t) const {
  std::vector<std::string> e;
  if (auto m = needs_tool(c, t)) e.push_back(*m);
  const auto& s = t.kind_spec<SpindleCurrentSpec>();
  if (!s.model.empty()) {
    const TestSpec* m = nullptr;
    for (const auto& other : c.tests) {
      if (other.id == s.model) m = &other;
    }
    if (!m) {
      e.push_back(t.yaml_label + ": key 'model' names '" + s.model +
                  "', which is not a test of the campaign");
    } else if (m->kind != "frf" && m->kind != "sweep-frf") {
      e.push_back(t.yaml_label + ": key 'model' names '" + s.model + "', a " + m->kind +
                  " test, not a frf or sweep-frf test");
    } else if (m->sample_rate_hz > 0 && t.sample_rate_hz > 0 &&
               std::abs(m->sample_rate_hz - t.sample_rate_hz) > 1e-9 * t.sample_rate_hz) {
      e.push_back(t.yaml_label + ": key 'model' names '" + s.model + "', a model at " +
                  fmt_sig(m->sample_rate_hz, 8) + " Hz; this test's sample_rate_hz is " +
                  fmt_sig(t.sample_rate_hz, 8) + " Hz (they must be equal)");
    }
  }
  if (!s.dyno_file.empty()) {
    const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s.dyno_file);
    if (!f.ok()) e.push_back(input_file_message(t.yaml_label, "dynamometer.file", f.problem));
  }
  return e;
}

std::vector<std::filesystem::path> SpindleCurrentKind::input_files(const TestSpec& t) const {
  const auto* s = dynamic_cast<const SpindleCurrentSpec*>(t.params.get());
  if (!s || s->dyno_file.empty()) return {};
  const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s->dyno_file);
  if (!f.ok()) return {};
  return {f.path};
}

std::vector<std::string> SpindleCurrentKind::required_channels(const TestSpec&) const {
  return {"current"};
}

namespace {

// The windows' lengths in samples of the record (`n` samples at `fs`), which the observer's
// friction mean and tooth-passing amplitude need.
std::optional<std::string> short_windows(const TestSpec& t, const SpindleCurrentSpec& s, double fs,
                                         Eigen::Index n) {
  if (sample_at(s.air_hi_s, fs, n) - sample_at(s.air_lo_s, fs, n) >= 2 &&
      sample_at(s.cut_hi_s, fs, n) - sample_at(s.cut_lo_s, fs, n) >= 2) {
    return std::nullopt;
  }
  return t.yaml_label + ": air_window_s and cut_window_s must each hold >= 2 samples";
}

// The dynamometer's torque (test.yaml `dynamometer.file`, column `torque`) resampled to the
// current's rate `fs`, at least `needed` samples long (the end of both windows), or InputError.
// The step and check_record read it alike.
Eigen::VectorXd read_dyno_torque(const TestSpec& t, const SpindleCurrentSpec& s, double fs,
                                 Eigen::Index needed) {
  const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s.dyno_file);
  if (!f.ok()) throw InputError(input_file_message(t.yaml_label, "dynamometer.file", f.problem));
  DataSpec d;
  d.file = f.path;
  d.relative_file = s.dyno_file;
  const std::string dlabel = t.file_label(s.dyno_file);
  const SignalTable dt = SignalTable::open(d, dlabel);
  if (!dt.has("torque")) throw InputError(dlabel + ": has no column 'torque' (N*m)");
  const Eigen::VectorXd raw = dt.channel("torque");
  if (!raw.allFinite()) throw InputError(dlabel + ": column torque has a non-finite sample");
  Eigen::VectorXd ref;
  try {
    ref = signal::RationalResampler(s.dyno_rate_hz, fs).apply(raw);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": key 'dynamometer.sample_rate_hz': " + e.what());
  }
  if (ref.size() < needed) {
    throw InputError(dlabel + ": ends at " + fmt_sig(raw.size() / s.dyno_rate_hz, 6) +
                     " s, before the end of air_window_s or cut_window_s");
  }
  return ref;
}

}  // namespace

std::vector<std::string> SpindleCurrentKind::check_record(const TestSpec& t,
                                                          double duration_s) const {
  const auto& s = t.kind_spec<SpindleCurrentSpec>();
  std::vector<std::string> e;
  for (const auto& [key, hi] :
       {std::pair<std::string, double>{"air_window_s", s.air_hi_s}, {"cut_window_s", s.cut_hi_s}}) {
    if (hi > duration_s * 1.0001) {
      e.push_back(t.yaml_label + ": key '" + key + "' ends at " + fmt_sig(hi, 6) +
                  " s, after the record (" + fmt_sig(duration_s, 6) + " s)");
    }
  }
  if (!e.empty()) return e;
  const double fs = t.sample_rate_hz;
  const auto n = static_cast<Eigen::Index>(std::llround(duration_s * fs));
  if (auto m = short_windows(t, s, fs, n)) return {*m};
  if (!s.dyno_file.empty()) {
    try {
      (void)read_dyno_torque(t, s, fs,
                             std::max(sample_at(s.cut_hi_s, fs, n), sample_at(s.air_hi_s, fs, n)));
    } catch (const InputError& x) {
      e.push_back(x.what());
    }
  }
  return e;
}

std::vector<Need> SpindleCurrentKind::needs(const TestSpec& t) const {
  return {{value::drive_model(t.kind_spec<SpindleCurrentSpec>().model), true}};
}

void SpindleCurrentKind::run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
                             TestOutcome& out) const {
  const auto& s = t.kind_spec<SpindleCurrentSpec>();
  const auto* drive = in.first<std::shared_ptr<const DriveModel>>(value::drive_model(s.model));
  if (!drive || !*drive) {
    out.status.fail("the model " + s.model + " is not available");
    return;
  }
  const DriveModel& dm = **drive;
  if (dm.input_unit != "N*m" || dm.output_unit != "A") {
    throw InputError(t.yaml_label + ": key 'model' names '" + s.model + "', a model from " +
                     dm.input_unit + " to " + dm.output_unit + "; the observer needs N*m to A");
  }
  if (std::abs(dm.model.sample_rate_hz - t.sample_rate_hz) > 1e-9 * t.sample_rate_hz) {
    throw InputError(t.yaml_label + ": key 'model': the model runs at " +
                     fmt_sig(dm.model.sample_rate_hz, 8) + " Hz, the current at " +
                     fmt_sig(t.sample_rate_hz, 8) + " Hz");
  }
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  const Eigen::VectorXd current = table.channel("current", t.channel("current"));
  const double fs = t.sample_rate_hz;
  const Eigen::Index n = current.size();
  auto res = std::make_unique<SpindleCurrentResult>();
  res->model_id = s.model;
  res->fs_hz = fs;
  const Eigen::Index a0 = sample_at(s.air_lo_s, fs, n), a1 = sample_at(s.air_hi_s, fs, n);
  res->cut_begin = sample_at(s.cut_lo_s, fs, n);
  res->cut_end = sample_at(s.cut_hi_s, fs, n);
  if (auto m = short_windows(t, s, fs, n)) throw InputError(*m);
  if (!current.allFinite()) throw InputError(label + ": channel current has a non-finite sample");
  // Step 1: the friction current of the air window (001 sec. 3.1).
  res->friction_current_A = current.segment(a0, a1 - a0).mean();
  const Eigen::VectorXd y = current.array() - res->friction_current_A;
  // Steps 2-3: R from the resolution, Q from the nominal cut (or the overrides).
  const ToolSpec& tool = *ctx.campaign->tool;
  sysid::NominalCut cut;
  cut.spindle_rpm = s.spindle_rpm;
  cut.teeth = tool.teeth;
  cut.tool_radius_m = tool.radius_m;
  cut.helix_deg = tool.helix_deg.value_or(0.0);
  cut.axial_depth_m = s.axial_depth_m;
  cut.radial_immersion_m = s.radial_immersion_m;
  cut.up_milling = s.up_milling;
  cut.feed_per_tooth_m = s.feed_per_tooth_m;
  cut.Ktc_N_m2 = s.Ktc_N_m2;
  cut.Kte_N_m = s.Kte_N_m;
  res->helix_deg = cut.helix_deg;
  double Q = 0.0;
  try {
    Q = s.Q_Nm2 ? *s.Q_Nm2 : sysid::torque_increment_variance(cut, fs);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": " + e.what());
  }
  res->Q_from_cut = !s.Q_Nm2;
  res->R_from_resolution = !s.R_A2;
  const double R = s.R_A2 ? *s.R_A2 : s.current_resolution_A * s.current_resolution_A / 12.0;
  if (!(Q > 0.0)) {
    out.status.fail("the nominal cut's torque does not change (Q = 0): give Ktc_N_m2 > 0 or Q_Nm2");
    return;
  }
  // Step 4: the observer.
  res->observer = sysid::design_torque_observer(dm.model, Q, R);
  out.warnings.insert(out.warnings.end(), res->observer.summary.warnings.begin(),
                      res->observer.summary.warnings.end());
  if (!res->observer.summary.ok()) {
    out.status.fail(res->observer.summary.message);
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  sysid::run_torque_observer(res->observer, y, &res->torque_Nm);
  res->observer_runtime_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Step 5: bandwidth.
  res->bandwidth_hz = sysid::observer_bandwidth_hz(res->observer);
  // Step 6: mean and tooth-passing amplitude over the cut window.
  const Eigen::Index c0 = res->cut_begin, cn = res->cut_end - res->cut_begin;
  const auto tau = res->torque_Nm.segment(c0, cn);
  res->torque_mean_Nm = tau.mean();
  res->tooth_pass_hz = tool.teeth * s.spindle_rpm / 60.0;
  std::complex<double> acc = 0.0;
  for (Eigen::Index k = 0; k < cn; ++k) {
    const double tk = static_cast<double>(c0 + k) / fs;
    acc += (tau[k] - res->torque_mean_Nm) * std::polar(1.0, -kTwoPi * res->tooth_pass_hz * tk);
  }
  res->tooth_pass_amplitude_Nm = 2.0 * std::abs(acc) / static_cast<double>(cn);
  // Step 7: the dynamometer, resampled to the current's rate.
  if (!s.dyno_file.empty()) {
    Eigen::VectorXd ref = read_dyno_torque(t, s, fs, std::max(res->cut_end, a1));
    ref.conservativeResize(std::min(ref.size(), n));
    const double air = ref.segment(a0, a1 - a0).mean();
    ref.array() -= air;
    res->reference_Nm = ref;
    const auto refc = ref.segment(c0, cn);
    const Eigen::VectorXd e = tau - refc;
    res->rmse_Nm = std::sqrt(e.squaredNorm() / static_cast<double>(cn));
    const double span = refc.maxCoeff() - refc.minCoeff();
    res->nrmse_pct = span > 0.0 ? 100.0 * res->rmse_Nm / span : std::nan("");
  }
  out.result = std::move(res);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, SpindleCurrentResult& r) {
  LAYOUT_GUARD(SpindleCurrentResult, 528);
  ar(r.model_id, r.fs_hz, r.friction_current_A, r.observer, r.bandwidth_hz, r.Q_from_cut,
     r.R_from_resolution, r.helix_deg, r.torque_Nm, r.reference_Nm, r.cut_begin, r.cut_end,
     r.torque_mean_Nm, r.tooth_pass_amplitude_Nm, r.tooth_pass_hz, r.rmse_Nm, r.nrmse_pct,
     r.observer_runtime_s);
}

std::string SpindleCurrentKind::save(const TestOutcome& out) const {
  return save_result<SpindleCurrentResult>(out);
}

void SpindleCurrentKind::restore(const TestSpec&, const std::string& bytes,
                                 TestOutcome& out) const {
  restore_result<SpindleCurrentResult>(bytes, out);
}

json SpindleCurrentKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<SpindleCurrentResult>();
  const auto& o = r.observer;
  json gain = json::array();
  for (Eigen::Index i = 0; i < o.K.size(); ++i) gain.push_back(o.K[i]);
  json j = {{"model", r.model_id},
            {"friction_current_A", r.friction_current_A},
            {"torque_file", spindle_torque_path(out.spec->id)},
            {"torque_mean_Nm", r.torque_mean_Nm},
            {"tooth_pass_amplitude_Nm", r.tooth_pass_amplitude_Nm},
            {"tooth_pass_hz", r.tooth_pass_hz},
            {"helix_deg", r.helix_deg},
            {"observer",
             {{"method", "kalman-random-walk-dare"},
              {"Q_Nm2", o.Q_Nm2},
              {"Q_source", r.Q_from_cut ? "nominal-cut" : "test.yaml"},
              {"R_A2", o.R_A2},
              {"R_source", r.R_from_resolution ? "resolution" : "test.yaml"},
              {"gain", gain},
              {"torque_gain", o.K[o.K.size() - 1]},
              {"bandwidth_hz", r.bandwidth_hz},
              {"dare_residual", number_or_null(o.dare_residual)},
              {"spectral_radius", number_or_null(o.spectral_radius)},
              {"form", o.modal ? "modal" : "dense"},
              {"steps", r.torque_Nm.size()},
              {"runtime_s", r.observer_runtime_s}}}};
  if (r.reference_Nm.size() > 0) {
    j["reference"] = {{"nrmse_pct", number_or_null(r.nrmse_pct)}, {"rmse_Nm", r.rmse_Nm}};
  }
  return j;
}

void SpindleCurrentKind::write_files(const TestOutcome& out,
                                     const std::filesystem::path& report_dir) const {
  const auto& r = out.result_of<SpindleCurrentResult>();
  const std::filesystem::path file = report_dir / spindle_torque_path(out.spec->id);
  std::filesystem::create_directories(file.parent_path());
  const Eigen::Index n = r.torque_Nm.size();
  Eigen::VectorXd t(n);
  for (Eigen::Index k = 0; k < n; ++k) t[k] = static_cast<double>(k) / r.fs_hz;
  // A plain table (format section 5: t, torque, a row per sample), numbers in their shortest
  // exact form.
  write_signals(file, {"t", "torque"}, {&t, &r.torque_Nm});
}

std::string SpindleCurrentKind::note(const TestOutcome& out) const {
  const auto& r = out.result_of<SpindleCurrentResult>();
  std::string s = "mean " + fmt_sig(r.torque_mean_Nm, 3) + " N*m, bandwidth " +
                  fmt_sig(r.bandwidth_hz, 4) + " Hz";
  if (r.reference_Nm.size() > 0) s += ", NRMSE " + fmt_sig(r.nrmse_pct, 3) + " %";
  return s;
}

render::Figure spindle_torque_figure(const SpindleCurrentResult& r) {
  // Time: five tooth periods from the start of the cut window.
  const Eigen::Index c0 = r.cut_begin;
  const Eigen::Index span = std::min<Eigen::Index>(
      r.cut_end - c0, static_cast<Eigen::Index>(std::ceil(5.0 * r.fs_hz / r.tooth_pass_hz)));
  std::vector<double> t, est, ref;
  for (Eigen::Index k = c0; k < c0 + span; ++k) {
    t.push_back(static_cast<double>(k) / r.fs_hz);
    est.push_back(r.torque_Nm[k]);
    if (r.reference_Nm.size() > k) ref.push_back(r.reference_Nm[k]);
  }
  render::Figure fig;
  fig.height_in = 5.0;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "time [s]";
  a.y_label = "torque [N*m]";
  if (!ref.empty()) {
    a.series.push_back({t, ref, "dynamometer", render::SeriesStyle::kLine, "#555555"});
  }
  a.series.push_back({t, est, "observer", render::SeriesStyle::kLine, "#D55E00"});
  // Amplitude spectra over the cut window (one FFT-free DFT per bin would be slow: a Goertzel
  // pass per harmonic of the tooth-passing frequency up to the observer bandwidth x 1.5).
  render::Axes& s = fig.panels.emplace_back();
  s.x_label = "frequency [Hz]";
  s.y_label = "amplitude [N*m]";
  s.log_y = true;
  std::vector<double> fh, ae, ar;
  const Eigen::Index cn = r.cut_end - c0;
  const double fmax = std::min(0.5 * r.fs_hz, 1.5 * r.bandwidth_hz + r.tooth_pass_hz);
  for (int h = 1; h * r.tooth_pass_hz < fmax && h <= 60; ++h) {
    const double f = h * r.tooth_pass_hz;
    std::complex<double> se = 0.0, sr = 0.0;
    for (Eigen::Index k = 0; k < cn; ++k) {
      const std::complex<double> w =
          std::polar(1.0, -kTwoPi * f * static_cast<double>(c0 + k) / r.fs_hz);
      se += r.torque_Nm[c0 + k] * w;
      if (r.reference_Nm.size() > c0 + k) sr += r.reference_Nm[c0 + k] * w;
    }
    fh.push_back(f);
    ae.push_back(2.0 * std::abs(se) / static_cast<double>(cn));
    ar.push_back(2.0 * std::abs(sr) / static_cast<double>(cn));
  }
  s.x_range = render::Range{0.0, fh.empty() ? fmax : fh.back() + r.tooth_pass_hz};
  if (!ref.empty()) {
    s.series.push_back(
        {fh, ar, "dynamometer, tooth-passing harmonics", render::SeriesStyle::kPoints, "#555555"});
  }
  s.series.push_back(
      {fh, ae, "observer, tooth-passing harmonics", render::SeriesStyle::kPoints, "#D55E00"});
  return fig;
}

render::Figure spindle_observer_response_figure(const SpindleCurrentResult& r) {
  const double nyq = 0.5 * r.fs_hz;
  const int n = 400;
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i)
    f[i] = std::pow(10.0, std::log10(1.0) + i * std::log10(nyq * 0.999) / (n - 1));
  const Eigen::VectorXcd H = sysid::torque_estimate_response(r.observer, f);
  std::vector<double> x(f.data(), f.data() + n), mag(n);
  for (int i = 0; i < n; ++i) mag[static_cast<std::size_t>(i)] = std::abs(H[i]);
  render::Figure fig;
  fig.height_in = 3.0;
  render::Axes& a = fig.panels.emplace_back();
  a.x_label = "frequency [Hz]";
  a.y_label = "|torque estimate / torque|";
  a.log_x = true;
  a.log_y = true;
  a.series = {{x, mag, "observer", render::SeriesStyle::kLine, "#0072B2"},
              {{r.bandwidth_hz, r.bandwidth_hz},
               {0.05, 2.0},
               "bandwidth " + fmt_sig(r.bandwidth_hz, 4) + " Hz",
               render::SeriesStyle::kDashedLine,
               "#555555"}};
  return fig;
}

void SpindleCurrentKind::figures(const CampaignResults&, const TestOutcome& out,
                                 FigureJobs& jobs) const {
  const auto& r = out.result_of<SpindleCurrentResult>();
  const std::string stem = figure_stem("spindle-current", out.spec->id);
  jobs.add(out.spec->id, "torque", stem + "torque", spindle_torque_figure(r));
  jobs.add(out.spec->id, "response", stem + "response", spindle_observer_response_figure(r));
}

json SpindleCurrentKind::report_section(const CampaignResults&,
                                        const std::vector<const TestOutcome*>& ok,
                                        const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<SpindleCurrentResult>();
    const auto& s = t->spec->kind_spec<SpindleCurrentSpec>();
    json j;
    j["id"] = t->spec->id;
    j["model"] = r.model_id;
    j["rpm"] = fmt_sig(s.spindle_rpm, 5);
    j["order"] = r.observer.model.order();
    j["friction_A"] = fmt_sig(r.friction_current_A, 4);
    j["Q"] = fmt_sig(r.observer.Q_Nm2, 3);
    j["Q_source"] = r.Q_from_cut ? "from the nominal cut (001 eqs 4.14-4.19)" : "from test.yaml";
    j["R"] = fmt_sig(r.observer.R_A2, 3);
    j["R_source"] = r.R_from_resolution ? "resolution&sup2;/12 (001 eq. 4.13)" : "from test.yaml";
    j["torque_gain"] = fmt_sig(r.observer.K[r.observer.K.size() - 1], 4);
    j["bandwidth_hz"] = fmt_sig(r.bandwidth_hz, 4);
    j["mean_Nm"] = fmt_sig(r.torque_mean_Nm, 4);
    j["tp_hz"] = fmt_sig(r.tooth_pass_hz, 4);
    j["tp_amp_Nm"] = fmt_sig(r.tooth_pass_amplitude_Nm, 4);
    j["has_reference"] = r.reference_Nm.size() > 0;
    j["rmse_Nm"] = fmt_sig(r.rmse_Nm, 3);
    j["nrmse_pct"] = fmt_sig(r.nrmse_pct, 3);
    j["runtime_ms"] = fmt_sig(r.observer_runtime_s * 1e3, 3);
    j["msps"] = fmt_sig(
        static_cast<double>(r.torque_Nm.size()) / std::max(r.observer_runtime_s, 1e-9) / 1e6, 3);
    j["form"] = r.observer.modal ? "modal" : "dense";
    j["figure_torque"] = figures.of(t->spec->id, "torque");
    j["figure_response"] = figures.of(t->spec->id, "response");
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "spindle-current"},
                                {"title", "Cutting torque from spindle current"}}})},
          {"spindle_tests", tests}};
}

void SpindleCurrentKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                       TruthComparison& c) const {
  const auto& r = out.result_of<SpindleCurrentResult>();
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  add_truth_row(c, "observer.Q_Nm2", id, truth_number(v, "Q_Nm2"), r.observer.Q_Nm2);
  add_truth_row(c, "observer.R_A2", id, truth_number(v, "R_A2"), r.observer.R_A2);
  add_truth_row(c, "tooth_pass_hz", id, truth_number(v, "tooth_pass_hz"), r.tooth_pass_hz);
}

}  // namespace chatterlab::app
