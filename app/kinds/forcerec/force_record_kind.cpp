// Kind `force-record` (format section 4, 004 ch. 3-4): a cut measured through a table
// dynamometer, its force reconstructed per axis by the AKF, the sliding-mode observer and
// regularized deconvolution (analysis/forcerec). See forcerec_kinds.h and docs/forcerec.md
// section 3. Figures, report section and truth comparison: force_record_report.cpp.
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/input_boundary.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/forcerec/forcerec_archive.h"
#include "app/kinds/forcerec/forcerec_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/results_json.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr const char* kMethodIds[3] = {"akf", "smo", "rd"};
constexpr char kAxes[3] = {'x', 'y', 'z'};

std::string channel_of(char axis) { return std::string("F") + axis; }

// Reads {x: v, y: v, z: v} of positive numbers (noise_var_N2) or strings (frf_tests).
template <class F>
void read_axis_map(const YAML::Node& root, YamlReader& r, const std::string& key, F&& each) {
  const YAML::Node m = root[key];
  if (!m) return;
  if (!m.IsMap()) {
    r.error(key, "must be a mapping {x: ..., y: ...}");
    return;
  }
  r.check_keys(m, {"x", "y", "z"}, key);
  for (char a : kAxes) {
    if (m[std::string(1, a)]) each(m, a);
  }
}

// The summary's failure or the exception's message as a method failure.
template <class F>
void run_method(ForceMethodResult& m, F&& body) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    body();
  } catch (const std::exception& e) {
    // The analysis layer throws std::invalid_argument for a record too short for a method
    // and InputError for options: either way this method has no result, the others go on.
    m.ok = false;
    m.message = e.what();
  }
  m.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void take_summary(ForceMethodResult& m, const StepSummary& s) {
  m.warnings.insert(m.warnings.end(), s.warnings.begin(), s.warnings.end());
  m.ok = s.ok();
  if (!m.ok) m.message = s.message;
}

struct MethodInputs {
  const ForceRecordSpec* spec = nullptr;
  double fs = 0.0;
  double tooth_freq_hz = 0.0;
  int harmonic_count = 0;
  double cut_begin_s = 0.0, cut_end_s = 0.0;
  forcerec::IndexWindow harmonic_window, evaluation_window;
  const Eigen::VectorXd* reference = nullptr;  // null or empty: none
};

// akf, smo and rd on one axis with one model.
std::array<ForceMethodResult, 3> reconstruct(const DynoModel& model, const Eigen::VectorXd& y,
                                             double R, const MethodInputs& in) {
  std::array<ForceMethodResult, 3> out;
  for (int i = 0; i < 3; ++i) out[static_cast<std::size_t>(i)].id = kMethodIds[i];
  const Eigen::Index N = y.size();
  const forcerec::DiscreteModel dm = forcerec::zoh(model.realization, in.fs);

  ForceMethodResult& akf = out[0];
  run_method(akf, [&] {
    forcerec::AkfOptions o;
    if (in.spec->akf_S_N2) {
      akf.akf = forcerec::reconstruct_force_akf_fixed_S(dm, y, R, *in.spec->akf_S_N2);
    } else {
      // E(S) over at least 1 s of the cut window after 0.05 s (format); a cut window too short
      // for that is tuned over the record from its start instead (a warning says so).
      forcerec::SampleWindow w =
          forcerec::akf_tuning_window(N, in.fs, in.cut_begin_s, in.cut_end_s, o);
      const auto skip = static_cast<Eigen::Index>(std::llround(o.skip_s * in.fs));
      if (w.end - w.begin <
          skip + static_cast<Eigen::Index>(std::llround(o.tuning_length_s * in.fs))) {
        const forcerec::SampleWindow whole =
            forcerec::akf_tuning_window(N, in.fs, 0.0, static_cast<double>(N) / in.fs, o);
        if (whole.end - whole.begin > w.end - w.begin) {
          akf.warnings.push_back(
              "the cut window holds less than 0.05 s + 1 s for E(S): S tuned "
              "over the record's first " +
              fmt_sig(static_cast<double>(whole.end - whole.begin) / in.fs, 3) + " s instead");
          w = whole;
        }
      }
      akf.akf = forcerec::reconstruct_force_akf(dm, y, R, w, o);
    }
    take_summary(akf, akf.akf.summary);
    if (akf.ok) {
      akf.tuning = akf.akf.S_N2;
      akf.force_N = std::move(akf.akf.force);
    }
  });

  ForceMethodResult& smo = out[1];
  run_method(smo, [&] {
    forcerec::SmoOptions o = in.spec->smo;
    o.tooth_freq_hz = in.tooth_freq_hz;
    o.harmonic_count = in.harmonic_count;
    smo.smo = forcerec::reconstruct_force_smo(model.realization, in.fs, y, o);
    take_summary(smo, smo.smo.summary);
    if (smo.ok) {
      smo.tuning = o.rho_N_s;
      smo.delta_N = o.delta_N;
      smo.a22s_1_s = o.a22s_1_s;
      smo.force_N = std::move(smo.smo.force);
      smo.smo.output_error_N.resize(0);
    }
  });

  ForceMethodResult& rd = out[2];
  run_method(rd, [&] {
    forcerec::DeconvolutionOptions o;
    o.rule = in.spec->rd_rule;
    o.fixed_alpha = in.spec->rd_alpha;
    rd.rd = forcerec::deconvolve_tikhonov(dm, y, R, o);
    take_summary(rd, rd.rd.summary);
    if (rd.ok) {
      rd.tuning = rd.rd.alpha;
      rd.force_N = std::move(rd.rd.force_N);
    }
  });

  for (auto& m : out) {
    if (!m.ok) continue;
    if (!m.force_N.allFinite() || m.force_N.size() != N) {
      m.ok = false;
      m.message = "the reconstructed force is not finite everywhere";
      m.force_N.resize(0);
      continue;
    }
    m.samples = m.force_N.size();
    if (in.harmonic_window.size() > 0) {
      m.has_harmonics = true;
      m.harmonics = forcerec::tooth_harmonics(m.force_N, in.harmonic_window, in.fs,
                                              in.tooth_freq_hz, in.harmonic_count);
    }
    if (in.reference && in.reference->size() == N && in.evaluation_window.size() > 0) {
      m.error = forcerec::reference_error(m.force_N, *in.reference, in.evaluation_window);
    }
  }
  return out;
}

json method_json(const ForceMethodResult& m, double fs, bool with_force_details) {
  json j;
  if (!m.ok) {
    j["status"] = "failed";
    j["message"] = m.message;
    return j;
  }
  j["samples"] = m.samples;
  j["runtime_s"] = m.runtime_s;
  j["mean_N"] = m.has_harmonics ? json(m.harmonics.mean_N) : json(nullptr);
  j["harmonics_N"] = m.harmonics.amplitudes_N;
  if (m.error) {
    j["nrmse_pct"] = m.error->nrmse_pct;
    j["fit_pct"] = m.error->fit_pct;
    j["lag_samples"] = m.error->lag_samples;
  }
  if (m.id == "akf") {
    j["S_N2"] = m.akf.S_N2;
    j["S_rule"] = m.akf.S_from_knee ? "knee" : "given";
    if (with_force_details) {
      j["R_N2"] = m.akf.R_N2;
      j["steady_state_spectral_radius"] = m.akf.spectral_radius;
      if (m.akf.S_from_knee) {
        j["tuning_window_s"] = {static_cast<double>(m.akf.tuning_window.begin) / fs,
                                static_cast<double>(m.akf.tuning_window.end) / fs};
      }
    }
  } else if (m.id == "smo") {
    j["rho_N_s"] = m.tuning;
    j["delta_N"] = m.delta_N;
    j["a22s_1_s"] = m.a22s_1_s;
    if (with_force_details) {
      j["B2_1_s"] = m.smo.B2_1_s;
      j["corner_hz"] = number_or_null(m.smo.corner_hz);
      j["effective_corner_hz"] = number_or_null(m.smo.effective_corner_hz);
      j["delay_samples"] = number_or_null(m.smo.delay_samples);
      j["amplitude_error_ratio"] = number_or_null(m.smo.amplitude_error);
      j["max_sampled_zero_modulus"] = number_or_null(m.smo.max_sampled_zero_modulus);
      j["bandwidth_warning"] = m.smo.bandwidth_warning;
    }
  } else {
    j["alpha"] = m.rd.alpha;
    j["alpha_rule"] = forcerec::to_string(m.rd.rule);
    if (with_force_details) {
      j["alpha_discrepancy"] = number_or_null(m.rd.alpha_discrepancy);
      j["alpha_gcv"] = number_or_null(m.rd.alpha_gcv);
      j["alpha_lcurve"] = number_or_null(m.rd.alpha_lcurve);
      j["discrepancy_satisfied"] = m.rd.discrepancy_satisfied;
      j["residual_norm_N"] = m.rd.residual_norm_N;
      j["solution_norm_N"] = m.rd.solution_norm_N;
      j["normal_equation_residual_ratio"] = m.rd.relative_residual;
    }
  }
  if (!m.warnings.empty()) j["warnings"] = m.warnings;
  return j;
}

}  // namespace

std::string force_file_path(const std::string& test_id) {
  std::string s = test_id.empty() ? std::string("root") : test_id;
  for (std::size_t i = s.find('/'); i != std::string::npos; i = s.find('/', i + 2)) {
    s.replace(i, 1, "__");
  }
  return "forces/" + s + ".f32";
}

std::vector<std::string> ForceRecordKind::keys() const {
  return {
      "operation",    "spindle_rpm",  "feed_per_tooth_mm", "axial_depth_mm", "radial_immersion_mm",
      "air_window_s", "noise_var_N2", "cut_window_s",      "frf_tests",      "akf_S_N2",
      "smo",          "rd_alpha"};
}

std::shared_ptr<const KindSpec> ForceRecordKind::parse(const YAML::Node& root,
                                                       YamlReader& r) const {
  auto s = std::make_shared<ForceRecordSpec>();
  if (auto op = r.optional_string(root, "operation")) {
    if (*op != "up-milling" && *op != "down-milling") {
      r.error("operation", "must be up-milling or down-milling, not '" + *op + "'");
    }
    s->operation = *op;
  }
  s->spindle_rpm = r.required_double(root, "spindle_rpm");
  if (root["spindle_rpm"] && !(s->spindle_rpm > 0)) r.error("spindle_rpm", "must be > 0");
  for (const char* k : {"feed_per_tooth_mm", "axial_depth_mm", "radial_immersion_mm"}) {
    if (auto v = r.optional_double(root, k); v && !(*v > 0)) r.error(k, "must be > 0");
  }
  s->air_window_s = read_interval(root, r, "air_window_s", false);
  s->cut_window_s = read_interval(root, r, "cut_window_s", false);
  read_axis_map(root, r, "noise_var_N2", [&](const YAML::Node& m, char a) {
    const std::string k(1, a);
    const double v = r.required_double(m, k, "noise_var_N2");
    if (!(v > 0)) {
      r.error("noise_var_N2." + k, "must be > 0 (N^2)");
    } else {
      s->noise_var_N2[a] = v;
    }
  });
  if (!s->air_window_s && !root["air_window_s"] && !root["noise_var_N2"]) {
    r.error("noise_var_N2",
            "is required when air_window_s is absent: the noise variance of each axis (N^2)");
  }
  read_axis_map(root, r, "frf_tests", [&](const YAML::Node& m, char a) {
    s->frf_tests[a] = r.required_string(m, std::string(1, a), "frf_tests");
  });
  if (const YAML::Node ref = root["reference"]; ref && ref.IsMap() && ref["force"]) {
    const YAML::Node f = ref["force"];
    if (!f.IsMap()) {
      r.error("reference.force", "must be {file: reference.f32, channels: [Fx, Fy]}");
    } else {
      r.check_keys(f, {"file", "channels"}, "reference.force");
      s->reference.relative_file = r.required_string(f, "file", "reference.force");
      s->reference.channels = r.string_list(f, "channels", true, "reference.force");
      s->has_reference = !s->reference.relative_file.empty() && !s->reference.channels.empty();
      for (const auto& c : s->reference.channels) {
        if (c != "Fx" && c != "Fy" && c != "Fz") {
          r.error("reference.force.channels",
                  "every channel must be Fx, Fy or Fz, not '" + c + "'");
          s->has_reference = false;
        }
      }
    }
  }
  if (const YAML::Node S = root["akf_S_N2"]) {
    if (S.IsScalar() && S.Scalar() == "knee") {
      s->akf_S_N2.reset();
    } else if (auto v = r.optional_double(root, "akf_S_N2")) {
      if (!(*v > 0)) {
        r.error("akf_S_N2", "must be knee or a number > 0 (N^2)");
      } else {
        s->akf_S_N2 = *v;
      }
    }
  }
  if (const YAML::Node m = root["smo"]) {
    if (!m.IsMap()) {
      r.error("smo", "must be a mapping {rho_N_s: 1.0e8, delta_N: 65, a22s_1_s: -1}");
    } else {
      r.check_keys(m, {"rho_N_s", "delta_N", "a22s_1_s"}, "smo");
      if (auto v = r.optional_double(m, "rho_N_s", "smo")) {
        if (!(*v > 0)) r.error("smo.rho_N_s", "must be > 0 (N/s)");
        s->smo.rho_N_s = *v;
      }
      if (auto v = r.optional_double(m, "delta_N", "smo")) {
        if (!(*v > 0)) r.error("smo.delta_N", "must be > 0 (N)");
        s->smo.delta_N = *v;
      }
      if (auto v = r.optional_double(m, "a22s_1_s", "smo")) {
        if (!(*v < 0)) r.error("smo.a22s_1_s", "must be < 0 (1/s): stable output-error dynamics");
        s->smo.a22s_1_s = *v;
      }
    }
  }
  if (const YAML::Node a = root["rd_alpha"]) {
    const std::string v = a.IsScalar() ? a.Scalar() : "";
    if (v == "discrepancy") {
      s->rd_rule = forcerec::AlphaRule::kDiscrepancy;
    } else if (v == "gcv") {
      s->rd_rule = forcerec::AlphaRule::kGcv;
    } else if (v == "lcurve") {
      s->rd_rule = forcerec::AlphaRule::kLcurve;
    } else if (auto x = r.optional_double(root, "rd_alpha")) {
      if (!(*x > 0)) {
        r.error("rd_alpha", "must be discrepancy, gcv, lcurve or a number > 0");
      } else {
        s->rd_rule = forcerec::AlphaRule::kFixed;
        s->rd_alpha = *x;
      }
    }
  }
  if (s->air_window_s && s->cut_window_s && s->air_window_s->second > s->cut_window_s->first &&
      s->air_window_s->first < s->cut_window_s->second) {
    r.error("air_window_s",
            "overlaps cut_window_s: the air window is spindle turning, tool not "
            "engaged");
  }
  return s;
}

std::vector<std::string> ForceRecordKind::check_campaign(const CampaignSpec& c,
                                                         const TestSpec& t) const {
  std::vector<std::string> e;
  if (auto m = needs_tool(c, t)) e.push_back(*m);
  const auto& s = t.kind_spec<ForceRecordSpec>();
  for (const auto& [axis, id] : s.frf_tests) {
    const std::string key = std::string("frf_tests.") + axis;
    const TestSpec* other = nullptr;
    for (const auto& o : c.tests) {
      if (o.id == id) other = &o;
    }
    if (!other) {
      e.push_back(t.yaml_label + ": key '" + key + "' names '" + id +
                  "', which is not a test of the campaign");
    } else if (other->kind != "dyno-frf") {
      e.push_back(t.yaml_label + ": key '" + key + "' names '" + id + "', a " + other->kind +
                  " test, not a dyno-frf test");
    } else if (const auto* os = dynamic_cast<const DynoFrfSpec*>(other->params.get());
               os && os->axis != axis) {
      e.push_back(t.yaml_label + ": key '" + key + "' names '" + id + "', whose axis is " +
                  std::string(1, os->axis));
    }
  }
  if (s.has_reference) {
    const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s.reference.relative_file);
    if (!f.ok()) e.push_back(t.yaml_label + ": key 'reference.force.file' " + f.problem);
  }
  return e;
}

std::vector<std::filesystem::path> ForceRecordKind::input_files(const TestSpec& t) const {
  const auto& s = t.kind_spec<ForceRecordSpec>();
  if (!s.has_reference) return {};
  const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s.reference.relative_file);
  if (!f.ok()) return {};
  return {f.path};
}

std::vector<std::string> ForceRecordKind::required_channels(const TestSpec&) const {
  return {"Fx", "Fy"};
}

namespace {

// The reference force of a test (test.yaml `reference.force`): each channel it names, as long
// as the record (`samples`) and finite, or InputError. The step and check_record read it alike.
std::map<char, Eigen::VectorXd> read_reference_force(const TestSpec& t, const ForceRecordSpec& s,
                                                     Eigen::Index samples) {
  std::map<char, Eigen::VectorXd> reference;
  DataSpec d = s.reference;
  d.file = resolve_input_file(t, "reference.force.file", d.relative_file);
  d.sample_rate_hz = 0.0;
  const std::string rl = t.file_label(d.relative_file);
  const SignalTable rt = SignalTable::open(d, rl);
  if (static_cast<Eigen::Index>(rt.samples()) != samples) {
    throw InputError(t.yaml_label + ": key 'reference.force.file': " + rl + " holds " +
                     std::to_string(rt.samples()) + " samples, the record " +
                     std::to_string(samples));
  }
  for (const auto& c : s.reference.channels) {
    reference[c[1]] = rt.channel(c);
    if (!reference[c[1]].allFinite()) {
      throw InputError(t.yaml_label + ": key 'reference.force.file': " + rl + " channel " + c +
                       " is not finite everywhere");
    }
  }
  return reference;
}

// The record's length against the format's evaluation window (0.05 s to the end less 0.01 s).
std::optional<std::string> evaluation_window_empty(const std::string& label, Eigen::Index samples,
                                                   double fs) {
  if (forcerec::evaluation_window(samples, fs).size() > 0) return std::nullopt;
  return label + ": " + std::to_string(samples) +
         " samples: the record is shorter than 0.06 s, the format's evaluation window (0.05 s to "
         "the end less 0.01 s) is empty";
}

}  // namespace

std::vector<std::string> ForceRecordKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<ForceRecordSpec>();
  std::vector<std::string> e;
  if (s.air_window_s) {
    if (auto m = window_outside(t, "air_window_s", s.air_window_s->second, duration_s)) {
      e.push_back(*m);
    }
  }
  if (s.cut_window_s) {
    if (auto m = window_outside(t, "cut_window_s", s.cut_window_s->second, duration_s)) {
      e.push_back(*m);
    }
  }
  const auto samples = static_cast<Eigen::Index>(std::llround(duration_s * t.sample_rate_hz));
  if (auto m = evaluation_window_empty(t.data_label(), samples, t.sample_rate_hz)) e.push_back(*m);
  if (s.has_reference) {
    try {
      (void)read_reference_force(t, s, samples);
    } catch (const InputError& x) {
      e.push_back(x.what());
    }
  }
  return e;
}

std::vector<Need> ForceRecordKind::needs(const TestSpec& t) const {
  const auto& s = t.kind_spec<ForceRecordSpec>();
  std::vector<Need> n;
  for (char a : kAxes) n.push_back({value::dyno_axis(a), false});
  for (const auto& [axis, id] : s.frf_tests) n.push_back({value::dyno_model(id), false});
  return n;
}

void ForceRecordKind::run(const TestSpec& t, const CampaignValues& in, const RunContext& ctx,
                          TestOutcome& out) const {
  const auto& s = t.kind_spec<ForceRecordSpec>();
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  const double fs = t.sample_rate_hz;
  auto res = std::make_unique<ForceRecordResult>();
  res->samples = static_cast<Eigen::Index>(table.samples());
  res->sample_rate_hz = fs;
  const Eigen::Index N = res->samples;
  const double T = static_cast<double>(N) / fs;
  res->teeth = ctx.campaign && ctx.campaign->tool ? ctx.campaign->tool->teeth : 0;
  res->tooth_freq_hz = s.spindle_rpm * res->teeth / 60.0;
  res->harmonic_count = forcerec::harmonic_count(fs, res->tooth_freq_hz);
  res->cut_begin_s = s.cut_window_s ? s.cut_window_s->first : 0.0;
  res->cut_end_s = s.cut_window_s ? s.cut_window_s->second : T;
  res->evaluation_window = forcerec::evaluation_window(N, fs);
  if (res->harmonic_count > 0) {
    res->harmonic_window =
        forcerec::harmonic_window(N, fs, res->tooth_freq_hz, res->cut_begin_s, res->cut_end_s);
  }
  if (res->harmonic_count == 0) {
    out.warnings.push_back("the tooth-passing frequency (" + fmt_sig(res->tooth_freq_hz, 5) +
                           " Hz) is above 0.4 sample_rate_hz: no harmonics");
  } else if (res->harmonic_window.size() == 0) {
    out.warnings.push_back(
        "the cut window holds no whole tooth period after 0.05 s: no "
        "harmonics");
  }
  if (auto m = evaluation_window_empty(label, N, fs)) throw InputError(*m);

  // The reference force (interval means, raw floats).
  const std::map<char, Eigen::VectorXd> reference =
      s.has_reference ? read_reference_force(t, s, N) : std::map<char, Eigen::VectorXd>{};

  for (char a : kAxes) {
    const std::string ch = channel_of(a);
    if (a == 'z' && !table.has(ch)) continue;
    ForceAxisResult ax;
    ax.axis = a;
    ax.measured_N = table.channel(ch, t.channel(ch));
    if (!ax.measured_N.allFinite()) {
      ax.skip_reason = label + ": channel " + ch + " is not finite everywhere";
      res->axes.push_back(std::move(ax));
      continue;
    }
    if (auto it = reference.find(a); it != reference.end()) ax.reference_N = it->second;
    if (res->harmonic_window.size() > 0) {
      ax.measured_harmonics = forcerec::tooth_harmonics(ax.measured_N, res->harmonic_window, fs,
                                                        res->tooth_freq_hz, res->harmonic_count);
    }
    if (ax.reference_N.size() == N && res->harmonic_window.size() > 0) {
      ax.reference_harmonics = forcerec::tooth_harmonics(ax.reference_N, res->harmonic_window, fs,
                                                         res->tooth_freq_hz, res->harmonic_count);
    }
    if (ax.reference_N.size() == N) {
      ax.measured_nrmse_pct =
          forcerec::nrmse_pct(ax.measured_N, ax.reference_N, res->evaluation_window);
    }
    // The model: frf_tests, else the only dyno-frf test of the axis.
    const auto models = in.all<std::shared_ptr<const DynoModel>>(value::dyno_axis(a));
    if (auto it = s.frf_tests.find(a); it != s.frf_tests.end()) {
      for (const auto& [id, m] : models) {
        if (id == it->second) ax.model = *m;
      }
      if (!ax.model) {
        ax.skip_reason =
            in.why_missing(value::dyno_model(it->second), "the dynamometer model of " + it->second);
      }
    } else if (models.size() == 1) {
      ax.model = *models.front().second;
    } else if (models.empty()) {
      ax.skip_reason = "no dyno-frf test of axis " + std::string(1, a) + " succeeded" +
                       (in.why_missing(value::dyno_axis(a)).empty()
                            ? ""
                            : ": " + in.why_missing(value::dyno_axis(a)));
    } else {
      std::string ids;
      for (const auto& [id, m] : models) ids += (ids.empty() ? "" : ", ") + id;
      ax.skip_reason = t.yaml_label + ": axis " + std::string(1, a) + " has " +
                       std::to_string(models.size()) + " dyno-frf tests (" + ids +
                       "): name one in key 'frf_tests." + std::string(1, a) + "'";
    }
    // R: the air window's variance, else noise_var_N2.
    if (!ax.model) {
      res->axes.push_back(std::move(ax));
      continue;
    }
    ax.frf_test = ax.model->id;
    if (s.air_window_s) {
      const auto k0 = static_cast<Eigen::Index>(std::ceil(s.air_window_s->first * fs));
      const auto k1 = std::min<Eigen::Index>(
          N, static_cast<Eigen::Index>(std::floor(s.air_window_s->second * fs)));
      if (k1 - k0 < 16) {
        throw InputError(t.yaml_label + ": key 'air_window_s' holds " +
                         std::to_string(std::max<Eigen::Index>(0, k1 - k0)) +
                         " samples: at least 16 are needed for the noise variance");
      }
      const auto seg = ax.measured_N.segment(k0, k1 - k0);
      ax.noise_var_N2 =
          (seg.array() - seg.mean()).square().sum() / static_cast<double>(k1 - k0 - 1);
      ax.noise_from_air = true;
    } else if (auto it = s.noise_var_N2.find(a); it != s.noise_var_N2.end()) {
      ax.noise_var_N2 = it->second;
    } else {
      ax.skip_reason = t.yaml_label + ": key 'noise_var_N2." + std::string(1, a) +
                       "' is missing (no air_window_s): the noise variance of the axis";
      res->axes.push_back(std::move(ax));
      continue;
    }
    if (!(ax.noise_var_N2 > 0)) {
      ax.skip_reason = t.yaml_label + ": the air window's variance of " + ch +
                       " is 0: a constant signal gives no noise level";
      res->axes.push_back(std::move(ax));
      continue;
    }
    MethodInputs mi;
    mi.spec = &s;
    mi.fs = fs;
    mi.tooth_freq_hz = res->tooth_freq_hz;
    mi.harmonic_count = res->harmonic_count;
    mi.cut_begin_s = res->cut_begin_s;
    mi.cut_end_s = res->cut_end_s;
    mi.harmonic_window = res->harmonic_window;
    mi.evaluation_window = res->evaluation_window;
    mi.reference = &ax.reference_N;
    ax.methods = reconstruct(*ax.model, ax.measured_N, ax.noise_var_N2, mi);
    ax.done = true;
    for (const auto& m : ax.methods) {
      for (const auto& w : m.warnings) {
        out.warnings.push_back(std::string(1, a) + ", " + m.id + ": " + w);
      }
      if (!m.ok) out.warnings.push_back(std::string(1, a) + ", " + m.id + " failed: " + m.message);
    }
    // The other models of the axis (a model that drifted, 004 sec. 4.5).
    for (const auto& [id, m] : models) {
      if (id == ax.frf_test) continue;
      ForceOtherModel o;
      o.frf_test = id;
      o.methods = reconstruct(**m, ax.measured_N, ax.noise_var_N2, mi);
      for (auto& mm : o.methods) mm.force_N.resize(0);
      ax.other_models.push_back(std::move(o));
    }
    res->axes.push_back(std::move(ax));
  }
  int done = 0;
  for (const auto& ax : res->axes) {
    if (ax.done) {
      ++done;
    } else {
      out.warnings.push_back("axis " + std::string(1, ax.axis) + " skipped: " + ax.skip_reason);
    }
  }
  if (done == 0) {
    std::string why;
    for (const auto& ax : res->axes) why += (why.empty() ? "" : "; ") + ax.skip_reason;
    out.status.fail("no axis could be reconstructed: " + why);
    out.failure = Failure::kInput;
    return;
  }
  out.result = std::move(res);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, ForceMethodResult& m) {
  LAYOUT_GUARD(ForceMethodResult, 936);
  ar(m.id, m.ok, m.message, m.warnings, m.runtime_s, m.force_N, m.samples, m.has_harmonics,
     m.harmonics, m.error, m.tuning, m.delta_N, m.a22s_1_s, m.akf, m.smo, m.rd);
}

template <class Ar>
void fields(Ar& ar, ForceOtherModel& o) {
  LAYOUT_GUARD(ForceOtherModel, 2840);
  ar(o.frf_test, o.methods);
}

template <class Ar>
void fields(Ar& ar, ForceAxisResult& a) {
  LAYOUT_GUARD(ForceAxisResult, 3056);
  ar(a.axis, a.done, a.skip_reason, a.frf_test, a.model, a.noise_var_N2, a.noise_from_air,
     a.measured_N, a.reference_N, a.measured_harmonics, a.reference_harmonics, a.measured_nrmse_pct,
     a.methods, a.other_models);
}

template <class Ar>
void fields(Ar& ar, ForceRecordResult& r) {
  LAYOUT_GUARD(ForceRecordResult, 112);
  ar(r.samples, r.sample_rate_hz, r.tooth_freq_hz, r.harmonic_count, r.teeth, r.cut_begin_s,
     r.cut_end_s, r.harmonic_window, r.evaluation_window, r.axes);
}

std::string ForceRecordKind::save(const TestOutcome& out) const {
  return save_result<ForceRecordResult>(out);
}

void ForceRecordKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<ForceRecordResult>(bytes, out);
}

json ForceRecordKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<ForceRecordResult>();
  json channels = json::array();
  json axes = json::object();
  for (const auto& ax : r.axes) {
    const std::string a(1, ax.axis);
    json j;
    if (!ax.done) {
      j["status"] = "skipped";
      j["skip_reason"] = ax.skip_reason;
      axes[a] = j;
      continue;
    }
    j["frf_test"] = ax.frf_test;
    j["noise_var_N2"] = ax.noise_var_N2;
    j["noise_var_source"] = ax.noise_from_air ? "air_window_s" : "noise_var_N2";
    const bool harm = r.harmonic_window.size() > 0;
    json meas = {{"mean_N", harm ? json(ax.measured_harmonics.mean_N) : json(nullptr)},
                 {"harmonics_N", ax.measured_harmonics.amplitudes_N}};
    if (ax.measured_nrmse_pct) meas["nrmse_pct"] = *ax.measured_nrmse_pct;
    j["measured"] = meas;
    if (ax.reference_harmonics) {
      j["reference"] = {{"mean_N", ax.reference_harmonics->mean_N},
                        {"harmonics_N", ax.reference_harmonics->amplitudes_N}};
    }
    json methods = json::object();
    for (const auto& m : ax.methods) {
      methods[m.id] = method_json(m, r.sample_rate_hz, true);
      if (m.ok) channels.push_back(m.id + "-" + a);
    }
    j["methods"] = methods;
    if (!ax.other_models.empty()) {
      json others = json::array();
      for (const auto& o : ax.other_models) {
        json oj = {{"frf_test", o.frf_test}};
        json om = json::object();
        for (const auto& m : o.methods) om[m.id] = method_json(m, r.sample_rate_hz, false);
        oj["methods"] = om;
        others.push_back(oj);
      }
      j["other_models"] = others;
    }
    axes[a] = j;
  }
  json d = {{"samples", r.samples},
            {"sample_rate_hz", r.sample_rate_hz},
            {"tooth_freq_hz", r.tooth_freq_hz},
            {"harmonic_count", r.harmonic_count},
            {"cut_window_s", {r.cut_begin_s, r.cut_end_s}},
            {"axes", axes}};
  d["harmonic_window_samples"] = r.harmonic_window.size();
  d["harmonic_window_s"] = {static_cast<double>(r.harmonic_window.begin) / r.sample_rate_hz,
                            static_cast<double>(r.harmonic_window.end) / r.sample_rate_hz};
  if (!channels.empty()) {
    d["force_file"] = {{"file", force_file_path(out.spec->id)}, {"channels", channels}};
  }
  return d;
}

void ForceRecordKind::write_files(const TestOutcome& out,
                                  const std::filesystem::path& report_dir) const {
  const auto& r = out.result_of<ForceRecordResult>();
  std::vector<const Eigen::VectorXd*> cols;
  for (const auto& ax : r.axes) {
    if (!ax.done) continue;
    for (const auto& m : ax.methods) {
      if (m.ok) cols.push_back(&m.force_N);
    }
  }
  if (cols.empty()) return;
  const std::filesystem::path file = report_dir / force_file_path(out.spec->id);
  std::filesystem::create_directories(file.parent_path());
  std::ofstream o = open_for_writing(file);
  // Little-endian interleaved floats, one row per record sample (format section 4).
  std::vector<float> row(cols.size());
  for (Eigen::Index k = 0; k < r.samples; ++k) {
    for (std::size_t c = 0; c < cols.size(); ++c) row[c] = static_cast<float>((*cols[c])(k));
    o.write(reinterpret_cast<const char*>(row.data()),
            static_cast<std::streamsize>(row.size() * sizeof(float)));
  }
  close_checked(o, file);
}

std::string ForceRecordKind::note(const TestOutcome& out) const {
  const auto& r = out.result_of<ForceRecordResult>();
  std::string n = fmt_sig(r.tooth_freq_hz, 4) + " Hz tooth passing";
  for (const auto& ax : r.axes) {
    if (!ax.done) {
      n += std::string(", ") + ax.axis + " skipped";
      continue;
    }
    if (!ax.measured_nrmse_pct) continue;
    n += std::string(", ") + ax.axis + " NRMSE " + fmt_sig(*ax.measured_nrmse_pct, 3) + " ->";
    for (const auto& m : ax.methods) {
      if (m.ok && m.error) n += " " + m.id + " " + fmt_sig(m.error->nrmse_pct, 3);
    }
    n += " %";
  }
  return n;
}

}  // namespace chatterlab::app
