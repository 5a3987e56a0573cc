// Kind `sifs-tap` (format section 6, 003 sec. 4.2.1): see sifs_kinds.h and docs/sifs.md.
#include <cmath>
#include <complex>
#include <filesystem>

#include "analysis/common/constants.h"
#include "app/core/archive_analysis.h"
#include "app/core/format.h"
#include "app/core/vectors.h"
#include "app/formats/frf_text.h"
#include "app/formats/uff58.h"
#include "app/kinds/common/frf_figure.h"
#include "app/kinds/common/hammer_hits.h"
#include "app/kinds/sifs/sifs_common.h"
#include "app/kinds/sifs/sifs_kinds.h"
#include "app/kinds/tap/tap_kind.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

// Lowest f > 0 on a 1 Hz grid up to nyquist_hz with | |G| - 1 | >= 0.1 (format step 7,
// "before"); nyquist_hz when there is none.
double bandwidth_before(const std::vector<sifs::SensorMode>& modes, double nyquist_hz) {
  for (double f = 1.0; f <= nyquist_hz; f += 1.0) {
    if (std::abs(std::abs(sifs::sensor_response(modes, f)) - 1.0) >= 0.1) return f;
  }
  return nyquist_hz;
}

// Local minima of |G| strictly between the lowest and highest natural frequency (1 Hz grid).
Eigen::VectorXd antiresonances(const std::vector<sifs::SensorMode>& modes) {
  std::vector<double> out;
  if (modes.size() < 2) return Eigen::VectorXd();
  const double lo = modes.front().fn_hz, hi = modes.back().fn_hz;
  double prev2 = std::abs(sifs::sensor_response(modes, lo));
  double prev = std::abs(sifs::sensor_response(modes, lo + 1.0));
  for (double f = lo + 2.0; f <= hi; f += 1.0) {
    const double g = std::abs(sifs::sensor_response(modes, f));
    if (prev < prev2 && prev <= g) out.push_back(f - 1.0);
    prev2 = prev;
    prev = g;
  }
  return Eigen::Map<const Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace

std::vector<std::string> SifsTapKind::keys() const {
  return {"axis", "hits", "band_hz", "modes", "tool_length_mm"};
}

std::shared_ptr<const KindSpec> SifsTapKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<SifsTapSpec>();
  s->axis = read_sifs_axis(root, r, false);
  s->tool_length_mm = read_tool_length(root, r);
  s->hits = read_hammer_hits(root, r);
  if (auto band = read_interval(root, r, "band_hz", true)) {
    s->band_lo_hz = band->first;
    s->band_hi_hz = band->second;
  }
  if (auto m = r.optional_double(root, "modes")) {
    if (*m < 1 || *m > 12 || std::floor(*m) != *m) {
      r.error("modes", "must be a whole number from 1 to 12");
    } else {
      s->modes = static_cast<int>(*m);
    }
  }
  return s;
}

std::vector<std::string> SifsTapKind::required_channels(const TestSpec&) const {
  std::vector<std::string> c{"hammer"};
  c.insert(c.end(), kWasherChannels.begin(), kWasherChannels.end());
  return c;
}

std::vector<std::string> SifsTapKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<SifsTapSpec>();
  std::vector<std::string> e = hammer_hits_outside(t, s.hits, duration_s);
  if (s.band_hi_hz > 0.5 * t.sample_rate_hz) {
    e.push_back(t.yaml_label + ": key 'band_hz' ends at " + fmt_sig(s.band_hi_hz, 6) +
                " Hz, above the Nyquist frequency (" + fmt_sig(0.5 * t.sample_rate_hz, 6) + " Hz)");
  }
  return e;
}

std::vector<Need> SifsTapKind::needs(const TestSpec&) const {
  return {{value::kSifsCalibration, true}};
}

std::vector<std::string> SifsTapKind::provides(const TestSpec& t) const {
  return {value::sifs_tap(t.id)};
}

std::string SifsTapKind::describe_value(const std::string& name) const {
  if (name.rfind("sifs-tap:", 0) == 0) return "the sensor model of " + name.substr(9);
  return "";
}

void SifsTapKind::run(const TestSpec& t, const CampaignValues& in, const RunContext&,
                      TestOutcome& out) const {
  const auto& s = t.kind_spec<SifsTapSpec>();
  const SifsCalibration* cal = in.first<SifsCalibration>(value::kSifsCalibration);
  if (!cal) {
    out.status.fail(in.why_missing(value::kSifsCalibration, "the sensor's calibration matrix"));
    out.failure = Failure::kInput;
    return;
  }
  const SignalTable table = SignalTable::open(t.data, t.data_label());
  const sifs::Washers w = read_washers(table, t);
  const sifs::Pairs p = sifs::pair_signals(w);
  const int k = static_cast<int>(s.axis);
  auto data = std::make_shared<SifsTapData>();
  data->id = t.id;
  data->axis = s.axis;
  data->fs_hz = t.sample_rate_hz;
  data->hammer_n = table.channel("hammer", t.channel("hammer"));
  const Eigen::Matrix3d C = calibration_for(*cal, t, s.tool_length_mm, out.warnings);
  data->response_n = p * C.row(k).transpose();
  const double fs = t.sample_rate_hz;
  data->windows = hammer_windows(t, s.hits, data->hammer_n, t.data_label(), out.warnings);
  auto res = std::make_unique<SifsTapResult>();
  try {
    res->frf = sifs::tap_frf(data->hammer_n, data->response_n, fs, data->windows);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": " + e.what());
  }
  if (!res->frf.summary.ok()) {
    out.status.fail(t.data_label() + ": " + res->frf.summary.message);
    return;
  }
  data->impact = res->frf.impact;
  data->r_tap_n = res->frf.r_tap_n;
  sifs::SensorFitOptions fo;
  fo.modes = s.modes;
  fo.band_lo_hz = s.band_lo_hz;
  fo.band_hi_hz = s.band_hi_hz;
  res->model = sifs::fit_sensor_model(res->frf, fo);
  out.warnings.insert(out.warnings.end(), res->model.summary.warnings.begin(),
                      res->model.summary.warnings.end());
  if (!res->model.summary.ok()) {
    out.status.fail(t.data_label() + ": modal fit: " + res->model.summary.message);
    return;
  }
  data->modes = res->model.modes;
  res->realization = sifs::realize_scaled_modal(res->model.modes);
  res->obsv_rcond =
      sifs::discrete_observability_rcond(res->realization.A, res->realization.C, 1.0 / fs);
  res->confidence = sifs::frf_confidence(res->frf);
  res->bandwidth_before_hz = bandwidth_before(res->model.modes, 0.5 * fs);
  res->antiresonances_hz = antiresonances(res->model.modes);
  if (res->frf.hits < 2) {
    out.warnings.push_back(
        "one hit: the coherence is 1 by construction and the FRF confidence bounds are zero");
  }
  res->data = std::move(data);
  out.result = std::move(res);
  out.status.succeed();
}

void SifsTapKind::publish(const TestOutcome& out, CampaignValues& values) const {
  values.put(value::sifs_tap(out.spec->id), out.spec->id, out.result_of<SifsTapResult>().data);
}

json SifsTapKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<SifsTapResult>();
  const auto& s = out.spec->kind_spec<SifsTapSpec>();
  json modes = json::array();
  for (const auto& m : r.model.modes) {
    modes.push_back({{"fn_hz", m.fn_hz}, {"zeta", m.zeta}, {"alpha", m.alpha}});
  }
  return {{"axis", sifs::to_string(s.axis)},
          {"hits", r.frf.hits},
          {"band_hz", {s.band_lo_hz, s.band_hi_hz}},
          {"modes", modes},
          {"static_gain", r.model.static_gain},
          {"fit_nrmse_pct", r.model.fit_nrmse_pct},
          {"realization", "scaled-modal"},
          {"cond_A", r.realization.cond_A},
          {"obsv_rcond", r.obsv_rcond},
          {"r_N", r.frf.r_tap_n},
          {"frf_csv", tap_frf_csv_path(out.spec->id)},
          {"frf_uff", tap_frf_uff_path(out.spec->id)},
          {"bandwidth_before_hz", r.bandwidth_before_hz},
          {"antiresonances_hz", to_vector(r.antiresonances_hz)}};
}

json SifsTapKind::settings(const CampaignSpec&) const {
  const sifs::TapOptions o;
  return {{"impact_fraction", o.impact_fraction},
          {"pre_impact_guard_s", o.pre_impact_guard_s},
          {"min_pre_impact_s", o.min_pre_impact_s},
          {"fit", "Levenberg-Marquardt on the complex H1, sqrt(coherence) weights, sum alpha = 1"},
          {"confidence", "003 eqs 6-3, 6-4 (phase in rad, B&P), bands at 2 sigma"}};
}

std::string SifsTapKind::note(const TestOutcome& out) const {
  const auto& r = out.result_of<SifsTapResult>();
  return std::to_string(r.frf.hits) + " hits, " + std::to_string(r.model.modes.size()) +
         " modes, fit " + fmt_sig(r.model.fit_nrmse_pct, 3) + " %";
}

render::Figure sifs_tap_figure(const SifsTapResult& t) {
  const auto& f = t.frf;
  FrfFigureData d;
  for (Eigen::Index i = 0; i < f.f_hz.size(); ++i) {
    const double fr = f.f_hz(i);
    if (fr > t.data->fs_hz * 0.45) break;
    const std::complex<double> g = sifs::sensor_response(t.model.modes, fr);
    d.f_hz.push_back(fr);
    d.measured_mag.push_back(std::abs(f.h1(i)));
    d.model_mag.push_back(std::abs(g));
    const double sm = t.confidence.magnitude_sigma.size() > i ? t.confidence.magnitude_sigma(i) : 0;
    d.band_lo.push_back(std::abs(f.h1(i)) - 2 * sm);
    d.band_hi.push_back(std::abs(f.h1(i)) + 2 * sm);
    d.measured_phase_deg.push_back(std::arg(f.h1(i)) * kRadToDeg);
    d.model_phase_deg.push_back(std::arg(g) * kRadToDeg);
    d.coherence.push_back(f.coherence(i));
  }
  return frf_model_figure(d,
                          {"|G| [N/N]", "H1 (taps)", "fit, eq. 4-27", "H1 +- 2 sigma (eq. 6-3)"});
}

// <test>/frf.csv (f_hz, re, im: H1 in sensor N per hammer N, coherence, fit_re, fit_im: the
// fitted sensor model, 003 eq. 4-27) and <test>/frf.uff (the same as UFF58: FRF records H1 and
// fit, function type 4, and the coherence, type 6), as the tap kind writes its own.
void SifsTapKind::write_files(const TestOutcome& out,
                              const std::filesystem::path& report_dir) const {
  const SifsTapResult& t = out.result_of<SifsTapResult>();
  const auto& f = t.frf;
  const Eigen::Index n = f.f_hz.size();
  if (n < 2) return;
  const std::string& id = out.spec->id;
  Eigen::VectorXcd fit(n);
  for (Eigen::Index i = 0; i < n; ++i) fit[i] = sifs::sensor_response(t.model.modes, f.f_hz[i]);
  std::filesystem::create_directories((report_dir / tap_frf_csv_path(id)).parent_path());
  frf_text::write_csv(report_dir / tap_frf_csv_path(id),
                      {"chatterlab " + std::string(CHATTERLAB_VERSION) + ", sifs-tap test " +
                           (id.empty() ? std::string(".") : id),
                       "sensor force per hammer force (N/N); re, im: H1 over the hits; fit_re, "
                       "fit_im: the fitted sensor model (003 eq. 4-27)"},
                      {{"f_hz", f.f_hz},
                       {"re", f.h1.real()},
                       {"im", f.h1.imag()},
                       {"coherence", f.coherence},
                       {"fit_re", fit.real()},
                       {"fit_im", fit.imag()}});
  const int direction = t.data && t.data->axis == sifs::Axis::kY ? 2 : 1;
  auto function = [&](const std::string& name, int type) {
    uff::Function58 u;
    u.id1 = name + " " + (id.empty() ? std::string(".") : id);
    u.id2 = "chatterlab " + std::string(CHATTERLAB_VERSION);
    u.id4 = "sifs-tap: spindle sensor per hammer force";
    u.function_type = type;
    u.response_entity = "sensor";
    u.reference_entity = "tool";
    u.response_node = u.reference_node = 1;
    u.response_direction = u.reference_direction = direction;
    u.x_start = f.f_hz[0];
    u.dx = f.df_hz;
    u.x_label = "Frequency";
    u.x_unit = "Hz";
    return u;
  };
  std::vector<uff::Function58> fs;
  for (const auto& [name, h] : {std::make_pair(std::string("H1"), Eigen::VectorXcd(f.h1)),
                                std::make_pair(std::string("fit"), fit)}) {
    uff::Function58 u = function(name, uff::kFrf);
    u.complex_ordinate = true;
    u.values = h;
    u.y_label = u.z_label = "Force";
    u.y_unit = u.z_unit = "N";
    fs.push_back(std::move(u));
  }
  if (f.coherence.size() == n) {
    uff::Function58 c = function("coherence", uff::kCoherence);
    c.real = f.coherence;
    c.y_label = "Coherence";
    fs.push_back(std::move(c));
  }
  uff::write_uff58(report_dir / tap_frf_uff_path(id), fs);
}

void SifsTapKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  jobs.add(out.spec->id, "frf", figure_stem("sifs-tap", out.spec->id) + "frf",
           sifs_tap_figure(out.result_of<SifsTapResult>()));
}

json SifsTapKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                                 const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<SifsTapResult>();
    json j;
    j["id"] = t->spec->id;
    j["axis"] = sifs::to_string(r.data->axis);
    j["hits"] = r.frf.hits;
    json modes = json::array();
    int i = 1;
    for (const auto& m : r.model.modes) {
      modes.push_back({{"n", i++},
                       {"fn_hz", fmt_sig(m.fn_hz, 4)},
                       {"zeta_pct", fmt_sig(m.zeta * 100, 3)},
                       {"alpha", fmt_sig(m.alpha, 3)}});
    }
    j["modes"] = modes;
    j["static_gain"] = fmt_sig(r.model.static_gain, 4);
    j["fit_nrmse_pct"] = fmt_sig(r.model.fit_nrmse_pct, 3);
    j["cond_A"] = fmt_sig(r.realization.cond_A, 3);
    j["obsv_rcond"] = fmt_sig(r.obsv_rcond, 3);
    j["r_N"] = fmt_sig(r.frf.r_tap_n, 3);
    j["bandwidth_before_hz"] = fmt_sig(r.bandwidth_before_hz, 4);
    std::string anti;
    for (Eigen::Index a = 0; a < r.antiresonances_hz.size(); ++a) {
      anti += (anti.empty() ? "" : ", ") + fmt_sig(r.antiresonances_hz(a), 4);
    }
    j["antiresonances"] = anti.empty() ? std::string("none") : anti + " Hz";
    j["figure"] = figures.of(t->spec->id, "frf");
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "sifs-tap"}, {"title", "Spindle sensor: tap tests"}}})},
          {"sifs_taps", tests}};
}

void SifsTapKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                TruthComparison& c) const {
  const auto& r = out.result_of<SifsTapResult>();
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  const YAML::Node modes = v["modes"];
  if (modes && modes.IsSequence()) {
    // Truth modes matched to fitted ones by nearest natural frequency.
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const double fn = truth_number(modes[i], "fn_hz");
      if (!std::isfinite(fn) || r.model.modes.empty()) continue;
      const sifs::SensorMode* best = &r.model.modes.front();
      for (const auto& m : r.model.modes) {
        if (std::abs(m.fn_hz - fn) < std::abs(best->fn_hz - fn)) best = &m;
      }
      const std::string q = "mode" + std::to_string(i + 1) + ".";
      add_truth_row(c, q + "fn_hz", id, fn, best->fn_hz);
      add_truth_row(c, q + "zeta", id, truth_number(modes[i], "zeta"), best->zeta);
      add_truth_row(c, q + "alpha", id, truth_number(modes[i], "alpha"), best->alpha);
    }
  }
  add_truth_row(c, "bandwidth_before_hz", id, truth_number(v, "bandwidth_before_hz"),
                r.bandwidth_before_hz);
  const double var = truth_number(v, "noise_var_N2");
  add_truth_row(c, "r_N", id, std::isfinite(var) ? std::sqrt(var) : var, r.frf.r_tap_n);
}

// ---- the per-test cache (app/core/archive.h) -------------------------------------------------

template <class Ar>
void fields(Ar& ar, SifsTapData& d) {
  LAYOUT_GUARD(SifsTapData, 160);
  ar(d.id, d.axis, d.modes, d.fs_hz, d.hammer_n, d.response_n, d.windows, d.impact, d.r_tap_n);
}

template <class Ar>
void fields(Ar& ar, SifsTapResult& r) {
  LAYOUT_GUARD(SifsTapResult, 488);
  ar(r.data, r.frf, r.model, r.realization, r.obsv_rcond, r.confidence, r.bandwidth_before_hz,
     r.antiresonances_hz);
}

std::string SifsTapKind::save(const TestOutcome& out) const {
  return save_result<SifsTapResult>(out);
}

void SifsTapKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<SifsTapResult>(bytes, out);
}

}  // namespace chatterlab::app
