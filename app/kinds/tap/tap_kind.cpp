#include "app/kinds/tap/tap_kind.h"

#include <cctype>
#include <cmath>
#include <complex>
#include <filesystem>
#include <set>

#include "analysis/common/constants.h"
#include "analysis/common/number_text.h"
#include "analysis/frf/hits.h"
#include "analysis/frf/mode.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/core/input_boundary.h"
#include "app/core/yaml_reader.h"
#include "app/formats/frf_text.h"
#include "app/formats/uff58.h"
#include "app/kinds/tap/tap_synth.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"
#include "app/synth/synth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

// test.yaml bounds stated in docs/format/campaign.md ("What the reader refuses").
constexpr long kMaxModes = 20;      // modes: fitted modes of one axis
constexpr double kMaxRecord = 1e6;  // frf.record: 1-based record number in a UFF file

// Appends a phase sample, breaking the line (NaN) where it wraps between +180 and -180 deg
// so that a wrap draws no vertical stroke across the panel.
void push_phase(render::Series& s, double f, double deg) {
  if (!s.y.empty() && std::isfinite(s.y.back()) && std::isfinite(deg) &&
      std::abs(deg - s.y.back()) > 180.0) {
    s.x.push_back(f);
    s.y.push_back(std::nan(""));
  }
  s.x.push_back(f);
  s.y.push_back(deg);
}

json tap_json(const TapOutcome& t, const std::string& id) {
  json j;
  if (t.from_file) {
    // No hits: the FRF came measured (docs/format/results-json.md, "kind tap").
    j["frf_source"] = "file";
    j["frf_input"] = (id.empty() ? "" : id + "/") + t.frf_file;
    j["frf_columns"] = t.frf_columns;
    if (std::isfinite(t.exp_window_tau_s)) j["exp_window_tau_s"] = t.exp_window_tau_s;
  } else {
    j["frf_source"] = "hits";
    j["hits_used"] = t.hits_used;
    json hits = json::array();
    for (const auto& h : t.hits) {
      json e = {{"time_s", h.time_s}, {"peak_force_N", h.peak_N}, {"accepted", h.accepted}};
      if (!h.accepted) e["rejected_because"] = h.reason;
      hits.push_back(e);
    }
    j["hits"] = hits;
    j["exp_window_tau_s"] = number_or_null(t.exp_window_tau_s);
  }
  j["frequency_resolution_hz"] = number_or_null(t.df_hz);
  // Files beside results.json (relative to it): the FRF table and file (the figure's files are
  // in the entry's `figures`, which results_json adds for every test).
  j["frf_csv"] = tap_frf_csv_path(id);
  j["frf_uff"] = tap_frf_uff_path(id);
  if (t.fit_ok) {
    json modes = json::array();
    for (std::size_t i = 0; i < t.modes.size(); ++i) {
      const auto& m = t.modes[i];
      const auto& q = t.quality.at(i);
      modes.push_back({{"fn_hz", m.fn_hz},
                       {"zeta", m.zeta},
                       {"m_kg", m.m_kg},
                       {"c_kg_s", m.c_kg_s},
                       {"k_N_m", m.k_N_m},
                       {"half_power_bins", q.half_power_bins},
                       {"resolution_limited", q.resolution_limited},
                       {"negative_modal_constant", q.negative_constant},
                       {"at_fit_bound", q.at_bound}});
    }
    j["modes"] = modes;
    j["fit_nrmse_pct"] = number_or_null(t.fit_nrmse_pct);
    j["fit_band_hz"] = {number_or_null(t.band_lo_hz), number_or_null(t.band_hi_hz)};
  } else {
    j["fit_status"] = "failed";
    j["fit_message"] = t.fit_message;
  }
  return j;
}

json tap_context(const TestOutcome& t, const std::string& figure) {
  const TapOutcome& tap = t.result_of<TapOutcome>();
  const TapSpec& spec = t.spec->kind_spec<TapSpec>();
  json j;
  j["id"] = t.spec->id;
  j["axis"] = spec.axis;
  j["response"] = spec.response;
  j["hits_used"] = tap.hits_used;
  j["hits_total"] = tap.hits.size();
  j["frf_from_file"] = tap.from_file;
  j["frf_file"] = tap.frf_file;
  j["df_hz"] = fmt_sig(tap.df_hz, 3);
  if (std::isfinite(tap.exp_window_tau_s)) j["exp_tau_ms"] = fmt_sig(tap.exp_window_tau_s * 1e3, 3);
  j["band_lo_hz"] = fmt_sig(tap.band_lo_hz, 4);
  j["band_hi_hz"] = fmt_sig(tap.band_hi_hz, 4);
  json rejected = json::array();
  for (const auto& h : tap.hits) {
    if (!h.accepted) rejected.push_back({{"t_s", fmt_fixed(h.time_s, 3)}, {"reason", h.reason}});
  }
  j["has_rejected"] = !rejected.empty();
  j["rejected"] = rejected;
  j["has_warnings"] = !t.warnings.empty();
  j["warnings"] = t.warnings;
  j["figure"] = figure;
  j["fit_ok"] = tap.fit_ok;
  j["fit_message"] = tap.fit_message;
  j["fit_nrmse_pct"] = fmt_fixed(tap.fit_nrmse_pct, 1);
  json modes = json::array();
  int n = 0;
  for (std::size_t i = 0; i < tap.modes.size(); ++i) {
    const auto& m = tap.modes[i];
    const auto& q = tap.quality.at(i);
    std::string note;
    if (q.resolution_limited) note = "\u03b6 from " + fmt_sig(q.half_power_bins, 2) + " bins";
    if (q.negative_constant) note += std::string(note.empty() ? "" : "; ") + "A < 0";
    if (q.at_bound) note += std::string(note.empty() ? "" : "; ") + "at fit bound";
    modes.push_back({{"n", ++n},
                     {"note", note},
                     {"fn_hz", fmt_sig(m.fn_hz, 5)},
                     {"zeta_pct", fmt_sig(100 * m.zeta, 3)},
                     {"m_kg", fmt_sig(m.m_kg, 4)},
                     {"c_kg_s", fmt_sig(m.c_kg_s, 4)},
                     {"k_N_m", fmt_sig(m.k_N_m, 4)}});
  }
  j["modes"] = modes;
  return j;
}

std::string hammer_value(const TestSpec& t) {
  return t.kind_spec<TapSpec>().axis == "y" ? value::kHammerModeY : value::kHammerModeX;
}

std::string hammer_modes_value(const TestSpec& t) {
  return t.kind_spec<TapSpec>().axis == "y" ? value::kHammerModesY : value::kHammerModesX;
}

}  // namespace

std::vector<std::string> TapKind::keys() const {
  return {"axis", "response", "hits", "band_hz", "modes", "frf"};
}

std::vector<std::string> TapKind::required_channels(const TestSpec& t) const {
  const auto* s = dynamic_cast<const TapSpec*>(t.params.get());
  if (s && s->frf) return {};
  return {"force", "response"};
}

// The record's length, which the step would refuse (validate and report run this alike).
// The hit windows inside the record, by the samples they take as the hit step does
// (analysis/frf/hits.cpp, hits_from_windows).
std::vector<std::string> TapKind::check_record(const TestSpec& t, double duration_s) const {
  const double samples = std::round(duration_s * t.sample_rate_hz);
  if (samples < frf::kMinTapRecordSamples) {
    return {t.yaml_label + ": key 'data.file' '" + t.data.relative_file + "': the record has " +
            fmt_sig(samples, 6) + " samples: a tap test needs at least " +
            std::to_string(frf::kMinTapRecordSamples)};
  }
  std::vector<std::string> errors;
  const auto& windows = t.kind_spec<TapSpec>().hit_windows_s;
  for (std::size_t i = 0; i < windows.size(); ++i) {
    const auto [start, end] = windows[i];  // finite (parse_tap)
    const double a = std::round(start * t.sample_rate_hz), b = std::round(end * t.sample_rate_hz);
    if (a < 0 || b > samples || b <= a) {
      errors.push_back(
          t.yaml_label + ": key 'hits' hit " + std::to_string(i + 1) + " [" +
          printf_text("%g", start) + ", " + printf_text("%g", end) +
          "] s: must satisfy 0 <= start < end <= " + printf_text("%g", samples / t.sample_rate_hz) +
          " s (the length of the record)");
    }
  }
  return errors;
}

// A measured FRF read as the step reads it (read_tap_frf): a file it would refuse.
std::vector<std::string> TapKind::check_files(const TestSpec& t) const {
  const auto* s = dynamic_cast<const TapSpec*>(t.params.get());
  if (!s || !s->frf || s->frf->file.empty()) return {};
  try {
    (void)read_tap_frf(t);
  } catch (const InputError& e) {
    return {e.what()};
  }
  return {};
}

std::vector<std::filesystem::path> TapKind::input_files(const TestSpec& t) const {
  const auto* s = dynamic_cast<const TapSpec*>(t.params.get());
  if (!s || !s->frf || s->frf->file.empty()) return {};
  const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s->frf->file);
  if (!f.ok()) return {};
  return {f.path};
}

std::vector<std::string> TapKind::check_campaign(const CampaignSpec&, const TestSpec& t) const {
  const auto* s = dynamic_cast<const TapSpec*>(t.params.get());
  if (!s || !s->frf || s->frf->file.empty()) return {};
  const InputFileCheck f = check_input_file(t.campaign_root, t.folder, s->frf->file);
  if (f.ok()) return {};
  return {input_file_message(t.yaml_label, "frf.file", f.problem)};
}

namespace {

// test.yaml `frf: {file, delimiter, decimal, record, exp_window_tau_s}`.
std::optional<TapFrfInput> parse_frf(const YAML::Node& root, YamlReader& r) {
  const YAML::Node node = root["frf"];
  if (!node) return std::nullopt;
  TapFrfInput in;
  if (!node.IsMap()) {
    r.error("frf", "must be a mapping such as {file: frf.csv}");
    return in;
  }
  r.check_keys(node, {"file", "delimiter", "decimal", "record", "exp_window_tau_s"}, "frf");
  in.file = r.required_string(node, "file", "frf");
  if (!in.file.empty()) {
    std::string ext = std::filesystem::path(in.file).extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    static const std::set<std::string> kText = {".csv", ".txt", ".tsv", ".dat", ".asc", ".frf"};
    if (!kText.count(ext) && ext != ".uff" && ext != ".unv") {
      r.error("frf.file", "'" + in.file +
                              "': unsupported FRF format (use text .csv, .txt, .tsv, .dat, .asc, "
                              ".frf or UFF58 .uff, .unv)");
    }
  }
  if (const auto d = r.optional_string(node, "delimiter", "frf")) {
    if (*d == "," || *d == ";") {
      in.delimiter = (*d)[0];
    } else if (*d == "tab" || *d == "\t" || *d == "\\t") {
      in.delimiter = '\t';
    } else if (*d == "whitespace" || *d == " ") {
      in.delimiter = ' ';
    } else {
      r.error("frf.delimiter", "'" + *d + "': must be ',', ';', tab or whitespace");
    }
  }
  if (const auto d = r.optional_string(node, "decimal", "frf")) {
    if (*d == "." || *d == ",") {
      in.decimal = (*d)[0];
    } else {
      r.error("frf.decimal", "'" + *d + "': must be '.' or ','");
    }
  }
  if (in.delimiter == ',' && in.decimal == ',') {
    r.error("frf.decimal", "',' needs another delimiter than ','");
  }
  if (const auto n = r.optional_double(node, "record", "frf")) {
    if (!(*n >= 1) || *n != std::floor(*n)) {
      r.error("frf.record", "must be a whole number >= 1");
    } else if (*n > kMaxRecord) {
      r.error("frf.record", "must be at most " + std::to_string(kMaxRecord) + " (a record number)");
    } else {
      in.record = static_cast<int>(*n);
    }
  }
  if (const auto tau = r.optional_double(node, "exp_window_tau_s", "frf")) {
    if (!(*tau >= 0)) {
      r.error("frf.exp_window_tau_s", "must be >= 0");
    } else {
      in.exp_window_tau_s = *tau;
    }
  }
  if (root["hits"]) r.error("hits", "not used with frf (a measured FRF has no hits)");
  if (root["data"]) {
    r.error("data",
            "not used with frf: give a time record with hits (data) or a measured FRF "
            "(frf), not both");
  }
  return in;
}

}  // namespace

std::shared_ptr<const KindSpec> TapKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto spec = std::make_shared<TapSpec>();
  TapSpec& s = *spec;
  s.axis = r.required_string(root, "axis");
  if (!s.axis.empty() && s.axis != "x" && s.axis != "y") {
    r.error("axis", "must be x or y, got '" + s.axis + "'");
  }
  s.response = r.required_string(root, "response");
  s.frf = parse_frf(root, r);
  if (!s.response.empty() && s.response != "acceleration" && s.response != "velocity" &&
      s.response != "displacement") {
    r.error("response", "must be acceleration, velocity or displacement, got '" + s.response + "'");
  }
  const YAML::Node hits = root["hits"];
  if (hits && hits.IsScalar() && hits.Scalar() != "auto") {
    r.error("hits", "must be 'auto' or a list of [start_s, end_s], got '" + hits.Scalar() + "'");
  } else if (hits && hits.IsSequence()) {
    s.hits_auto = false;
    for (const auto& h : hits) {
      if (!h.IsSequence() || h.size() != 2) {
        r.error("hits", "each hit must be a list [start_s, end_s]");
        break;
      }
      try {
        const double a = h[0].as<double>(), b = h[1].as<double>();
        if (!std::isfinite(a) || !std::isfinite(b)) {
          r.error("hits", "each hit must be two finite numbers [start_s, end_s], got [" +
                              printf_text("%g", a) + ", " + printf_text("%g", b) + "]");
          break;
        }
        if (!(b > a)) r.error("hits", "each hit window needs end_s > start_s");
        s.hit_windows_s.emplace_back(a, b);
      } catch (const YAML::Exception&) {
        r.error("hits", "each hit must be a list of two numbers [start_s, end_s]");
        break;
      }
    }
  } else if (hits && !hits.IsScalar()) {
    r.error("hits", "must be 'auto' or a list of [start_s, end_s]");
  }
  s.band_hz = r.optional_pair(root, "band_hz");
  if (s.band_hz && !(s.band_hz->second > s.band_hz->first && s.band_hz->first >= 0)) {
    r.error("band_hz", "must be [low, high] with 0 <= low < high");
  }
  const YAML::Node modes = root["modes"];
  if (modes && !(modes.IsScalar() && modes.Scalar() == "auto")) {
    // 'auto' or a whole number from 1 to kMaxModes (never converted unchecked: 1e300 is refused).
    if (const auto m = r.optional_int(root, "modes", "", 1, kMaxModes))
      s.modes = static_cast<int>(*m);
  }
  return spec;
}

std::vector<std::string> TapKind::provides(const TestSpec& t) const {
  return {hammer_value(t), hammer_modes_value(t)};
}

std::string TapKind::describe_value(const std::string& name) const {
  if (name == value::kHammerModeX) return "the hammer-test mode of x";
  if (name == value::kHammerModeY) return "the hammer-test mode of y";
  if (name == value::kHammerModesX) return "the hammer-test modes of x";
  if (name == value::kHammerModesY) return "the hammer-test modes of y";
  return "";
}

void TapKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                  TestOutcome& out) const {
  out.adopt(std::make_unique<TapOutcome>(run_tap_test(t, options_)));
}

template <class Ar>
void fields(Ar& ar, TapHitInfo& h) {
  LAYOUT_GUARD(TapHitInfo, 56);
  ar(h.time_s, h.peak_N, h.accepted, h.reason);
}

template <class Ar>
void fields(Ar& ar, TapOutcome& o) {
  LAYOUT_GUARD(TapOutcome, 448);
  ar(o.summary, o.from_file, o.frf_file, o.frf_columns, o.has_coherence, o.warnings, o.hits,
     o.hits_used, o.f_hz, o.h1, o.h2, o.coherence, o.df_hz, o.exp_window_tau_s, o.fit_ok,
     o.fit_message, o.modes, o.quality, o.fit_nrmse_pct, o.band_lo_hz, o.band_hi_hz, o.fitted);
}

std::string TapKind::save(const TestOutcome& out) const { return save_result<TapOutcome>(out); }

void TapKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<TapOutcome>(bytes, out);
}

void TapKind::publish(const TestOutcome& out, CampaignValues& values) const {
  const TapOutcome& tap = out.result_of<TapOutcome>();
  const std::string id = out.spec->id;
  // The tool mode: the fitted mode of largest peak receptance (frf::dominant_mode).
  const std::optional<frf::Mode> m = tap.fit_ok ? frf::dominant_mode(tap.modes) : std::nullopt;
  if (m) {
    values.put(hammer_value(*out.spec), id, *m);
  } else {
    values.fail(hammer_value(*out.spec), id, "its modal fit failed: " + tap.fit_message);
  }
  if (tap.fit_ok && !tap.modes.empty()) {
    values.put(hammer_modes_value(*out.spec), id, tap.modes);
  } else {
    values.fail(hammer_modes_value(*out.spec), id, "its modal fit failed: " + tap.fit_message);
  }
}

json TapKind::results(const TestOutcome& out) const {
  return tap_json(out.result_of<TapOutcome>(), out.spec->id);
}

std::string tap_frf_csv_path(const std::string& test_id) {
  return (test_id.empty() ? std::string() : test_id + "/") + "frf.csv";
}

void write_tap_frf_csv(const TapOutcome& tap, const std::string& test_id,
                       const std::filesystem::path& file) {
  const Eigen::Index n = tap.f_hz.size();
  auto part = [&](const Eigen::VectorXcd& h, bool imag) {
    Eigen::VectorXd v = Eigen::VectorXd::Constant(n, std::nan(""));
    for (Eigen::Index i = 0; i < std::min(n, h.size()); ++i)
      v[i] = imag ? h[i].imag() : h[i].real();
    return v;
  };
  std::vector<std::string> comments = {
      "chatterlab " + std::string(CHATTERLAB_VERSION) + ", tap test " +
          (test_id.empty() ? std::string(".") : test_id),
      "receptance in m/N; re, im: H1" +
          std::string(tap.from_file ? " (as read from " + tap.frf_file + ")" : "") +
          "; h2_re, h2_im: H2; fit_re, fit_im: the fitted modal model (empty when the fit failed)"};
  if (std::isfinite(tap.exp_window_tau_s)) {
    comments.push_back(
        "exponential window tau = " + fmt_sig(tap.exp_window_tau_s, 6) +
        " s applied to H1, H2 and the fit (frf: {exp_window_tau_s} to read it back)");
  }
  if (tap.fit_ok) {
    comments.push_back("fit band " + fmt_sig(tap.band_lo_hz, 6) + " - " +
                       fmt_sig(tap.band_hi_hz, 6) + " Hz; the model is written on every row");
  }
  Eigen::VectorXd coh = tap.coherence.size() == n ? tap.coherence : Eigen::VectorXd::Ones(n);
  std::vector<frf_text::Column> cols = {
      {"f_hz", tap.f_hz},
      {"re", part(tap.h1, false)},
      {"im", part(tap.h1, true)},
      {"coherence", coh},
      {"h2_re", part(tap.h2, false)},
      {"h2_im", part(tap.h2, true)},
      {"fit_re", part(tap.fit_ok ? tap.fitted : Eigen::VectorXcd(), false)},
      {"fit_im", part(tap.fit_ok ? tap.fitted : Eigen::VectorXcd(), true)}};
  // An FRF read from a file has no H2 (it would repeat H1) and a coherence only if the file had.
  if (tap.from_file) cols.erase(cols.begin() + 4, cols.begin() + 6);
  if (!tap.has_coherence) cols.erase(cols.begin() + 3);
  std::filesystem::create_directories(file.parent_path());
  frf_text::write_csv(file, comments, cols);
}

std::string tap_frf_uff_path(const std::string& test_id) {
  return (test_id.empty() ? std::string() : test_id + "/") + "frf.uff";
}

void write_tap_frf_uff(const TapOutcome& tap, const std::string& test_id, const std::string& axis,
                       const std::filesystem::path& file) {
  const std::string id = test_id.empty() ? std::string(".") : test_id;
  const int direction = axis == "y" ? 2 : 1;
  auto function = [&](const std::string& name, int type) {
    uff::Function58 f;
    f.id1 = name + " " + id;
    f.id2 = "chatterlab " + std::string(CHATTERLAB_VERSION);
    f.id4 = tap.from_file ? "measured FRF read from " + tap.frf_file : "impact hammer test";
    f.function_type = type;
    f.response_entity = f.reference_entity = "tool";
    f.response_node = f.reference_node = 1;
    f.response_direction = f.reference_direction = direction;
    f.x_start = tap.f_hz[0];
    f.dx = tap.df_hz;
    // Bins that are not evenly spaced to the printed precision of dx: every abscissa value.
    for (Eigen::Index i = 0; i < tap.f_hz.size(); ++i) {
      if (std::abs(tap.f_hz[i] - (f.x_start + static_cast<double>(i) * f.dx)) > 1e-9 * f.dx) {
        f.x = tap.f_hz;
        break;
      }
    }
    f.x_label = "Frequency";
    f.x_unit = "Hz";
    return f;
  };
  std::vector<uff::Function58> fs;
  auto add_frf = [&](const std::string& name, const Eigen::VectorXcd& h) {
    uff::Function58 f = function(name, uff::kFrf);
    f.complex_ordinate = true;
    f.values = h;
    f.y_label = "Displacement";
    f.y_unit = "m";
    f.z_label = "Force";
    f.z_unit = "N";
    fs.push_back(std::move(f));
  };
  add_frf("H1", tap.h1);
  if (!tap.from_file) add_frf("H2", tap.h2);
  if (tap.fit_ok && tap.fitted.size() == tap.f_hz.size()) add_frf("fit", tap.fitted);
  if (tap.has_coherence && tap.coherence.size() == tap.f_hz.size()) {
    uff::Function58 c = function("coherence", uff::kCoherence);
    c.real = tap.coherence;
    c.y_label = "Coherence";
    c.y_unit = "";
    fs.push_back(std::move(c));
  }
  std::filesystem::create_directories(file.parent_path());
  uff::write_uff58(file, fs);
}

void TapKind::write_files(const TestOutcome& out, const std::filesystem::path& report_dir) const {
  const TapOutcome& tap = out.result_of<TapOutcome>();
  if (tap.f_hz.size() < 2) return;
  const std::string& id = out.spec->id;
  write_tap_frf_csv(tap, id, report_dir / tap_frf_csv_path(id));
  write_tap_frf_uff(tap, id, out.spec->kind_spec<TapSpec>().axis,
                    report_dir / tap_frf_uff_path(id));
}

json TapKind::settings(const CampaignSpec&) const {
  const auto& h = options_.hits;
  const auto& f = options_.frf;
  const auto& m = options_.fit;
  return {{"hits",
           {{"threshold_fraction", h.threshold_fraction},
            {"noise_multiple", h.noise_multiple},
            {"pretrigger_s", h.pretrigger_s},
            {"double_hit_window_s", h.double_hit_window_s},
            {"max_record_s", h.max_record_s},
            {"min_record_fraction", h.min_record_fraction},
            {"clip_min_samples", h.clip_min_samples},
            {"clip_tolerance", h.clip_tolerance}}},
          {"frf",
           {{"force_window_margin", f.force_window_margin},
            {"exp_window_auto", f.exp_window_auto},
            {"exp_window_tau_s", f.exp_window_tau_s},
            {"exp_window_end_fraction", f.exp_window_end_fraction},
            {"decay_segment_fraction", f.decay_segment_fraction}}},
          {"fit",
           {{"estimator", m.estimator == frf::FrfEstimator::kH1 ? "H1" : "H2"},
            {"residual_terms", m.residual_terms},
            {"min_frequency_hz", m.min_frequency_hz},
            {"min_coherence", m.min_coherence},
            {"min_prominence_db", m.min_prominence_db},
            {"band_dominance_db", m.band_dominance_db},
            {"mode_floor_db", m.mode_floor_db},
            {"max_modes", m.max_modes},
            {"resolution_warning_bins", m.resolution_warning_bins},
            {"max_iterations", m.max_iterations}}}};
}

std::string TapKind::note(const TestOutcome& out) const {
  const TapOutcome& tap = out.result_of<TapOutcome>();
  if (!tap.fit_ok) return "FRF only; fit failed";
  return std::to_string(tap.modes.size()) + " mode(s), first at " +
         fmt_sig(tap.modes.front().fn_hz, 4) + " Hz";
}

void TapKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  const TapOutcome& tap = out.result_of<TapOutcome>();
  if (tap.f_hz.size() < 2) return;
  const std::string stem = figure_stem("tap", out.spec->id);
  jobs.add(out.spec->id, "frf", stem + "frf", tap_frf_figure(tap));
}

json TapKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                             const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) tests.push_back(tap_context(*t, figures.of(t->spec->id, "frf")));
  return {{"toc", json::array({{{"anchor", "tap"}, {"title", "Tap tests"}}})},
          {"tap_tests", tests}};
}

// Tap test: the truth's modes matched to the fitted mode nearest in frequency.
void TapKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                            TruthComparison& c) const {
  const TapOutcome& tap = out.result_of<TapOutcome>();
  const YAML::Node& v = *in.entry;
  if (!tap.fit_ok || !v["modes"]) return;
  const std::string key = out.spec->id;
  int i = 0;
  for (const auto& m : v["modes"]) {
    ++i;
    const double fn = truth_number(m, "fn_hz");
    const frf::Mode* best = nullptr;
    for (const auto& fm : tap.modes) {
      if (!best || std::abs(fm.fn_hz - fn) < std::abs(best->fn_hz - fn)) best = &fm;
    }
    if (!best || std::abs(best->fn_hz - fn) > 0.1 * fn) continue;  // mode not found
    const std::string p = "mode" + std::to_string(i) + ".";
    add_truth_row(c, p + "fn_hz", key, fn, best->fn_hz);
    add_truth_row(c, p + "zeta", key, truth_number(m, "zeta"), best->zeta);
    add_truth_row(c, p + "m_kg", key, truth_number(m, "m_kg"), best->m_kg);
    add_truth_row(c, p + "c_kg_s", key, truth_number(m, "c_kg_s"), best->c_kg_s);
    add_truth_row(c, p + "k_N_m", key, truth_number(m, "k_N_m"), best->k_N_m);
  }
}

render::Figure tap_frf_figure(const TapOutcome& tap) {
  // Shown range: around the fit band (or the whole FRF when no fit), within the FRF's range.
  double lo = tap.f_hz.size() ? tap.f_hz[0] : 1.0;
  double hi = tap.f_hz.size() ? tap.f_hz[tap.f_hz.size() - 1] : 2.0;
  if (std::isfinite(tap.band_lo_hz) && std::isfinite(tap.band_hi_hz)) {
    lo = std::max(lo, tap.band_lo_hz / 1.5);
    hi = std::min(hi, tap.band_hi_hz * 1.5);
  }
  render::Series mag1, mag2, fit_mag, ph1, fit_ph, coh;
  mag1.label = "H1";
  mag2.label = "H2";
  mag2.style = render::SeriesStyle::kDashedLine;
  fit_mag.label = "fit";
  fit_mag.style = render::SeriesStyle::kDashedLine;
  ph1.label = "H1";
  fit_ph.label = "fit";
  fit_ph.style = render::SeriesStyle::kDashedLine;
  coh.label = "coherence";
  for (Eigen::Index i = 0; i < tap.f_hz.size(); ++i) {
    const double f = tap.f_hz[i];
    if (f < lo || f > hi) continue;
    mag1.x.push_back(f);
    mag1.y.push_back(std::abs(tap.h1[i]));
    mag2.x.push_back(f);
    mag2.y.push_back(std::abs(tap.h2[i]));
    push_phase(ph1, f, std::arg(tap.h1[i]) * kRadToDeg);
    coh.x.push_back(f);
    coh.y.push_back(tap.coherence[i]);
    if (tap.fit_ok && tap.fitted.size() == tap.f_hz.size()) {
      const bool in_band = f >= tap.band_lo_hz && f <= tap.band_hi_hz;
      fit_mag.x.push_back(f);
      fit_mag.y.push_back(in_band ? std::abs(tap.fitted[i]) : std::nan(""));
      push_phase(fit_ph, f, in_band ? std::arg(tap.fitted[i]) * kRadToDeg : std::nan(""));
    }
  }
  mag1.color = ph1.color = "#0072B2";
  mag2.color = "#56B4E9";
  fit_mag.color = fit_ph.color = "#D55E00";
  coh.color = "#009E73";
  render::Figure fig;
  fig.share_x = true;
  fig.height_in = 5.4;
  render::Axes& a = fig.panels.emplace_back();
  a.y_label = "|receptance| [m/N]";
  a.log_x = a.log_y = true;
  a.relative_height = 2.2;
  // A measured FRF read from a file has no H2 (H2 = H1) and a coherence only if the file had one.
  if (tap.from_file) {
    mag1.label = ph1.label = "measured";
    a.series = {mag1};
  } else {
    a.series = {mag1, mag2};
  }
  if (!fit_mag.x.empty()) a.series.push_back(fit_mag);
  render::Axes& p = fig.panels.emplace_back();
  p.y_label = "phase [deg]";
  p.log_x = true;
  p.y_range = render::Range{-180, 180};
  p.relative_height = 1.2;
  p.series = {ph1};
  if (!fit_ph.x.empty()) p.series.push_back(fit_ph);
  p.legend = render::LegendPosition::kNone;
  if (!tap.has_coherence) {
    fig.height_in = 4.4;
    fig.panels.back().x_label = "frequency [Hz]";
    for (auto& ax : fig.panels) ax.x_range = render::Range{lo, hi};
    return fig;
  }
  render::Axes& c = fig.panels.emplace_back();
  c.x_label = "frequency [Hz]";
  c.y_label = "coherence [-]";
  c.log_x = true;
  c.y_range = render::Range{0, 1.05};
  c.relative_height = 1.0;
  c.series = {coh};
  c.legend = render::LegendPosition::kNone;
  // Not through a, p, c: emplace_back may have moved the earlier panels.
  for (auto& ax : fig.panels) ax.x_range = render::Range{lo, hi};
  return fig;
}

std::shared_ptr<const KindSpec> TapKind::parse_synth(const YAML::Node& section,
                                                     const SynthContext& ctx, YamlReader& r) const {
  (void)ctx;
  return std::make_shared<TapSynthSpec>(read_tap_synth(section, r));
}

int TapKind::write_synth(const KindSpec& section, SynthContext& ctx) const {
  return write_tap_tests(dynamic_cast<const TapSynthSpec&>(section), ctx);
}

}  // namespace chatterlab::app
