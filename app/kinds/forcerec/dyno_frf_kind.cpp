// Kind `dyno-frf` (format section 4, 004 sec. 3.1): see forcerec_kinds.h and docs/forcerec.md.
#include <algorithm>
#include <cmath>
#include <complex>

#include "analysis/common/constants.h"
#include "app/core/format.h"
#include "app/core/signals.h"
#include "app/core/yaml_reader.h"
#include "app/kinds/common/conditions.h"
#include "app/kinds/common/frf_figure.h"
#include "app/kinds/forcerec/forcerec_archive.h"
#include "app/kinds/forcerec/forcerec_kinds.h"
#include "app/pipeline/cached_result.h"
#include "app/report/figure_jobs.h"
#include "app/report/results_json.h"
#include "app/report/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

// The default fit band (format section 4): [50, min(4000, 0.4 sample_rate_hz)] Hz.
constexpr double kDefaultBandLoHz = 50.0;
constexpr double kDefaultBandHiHz = 4000.0;
constexpr double kDefaultBandHiFraction = 0.4;
constexpr int kMaxOrder = 20;  // ten modes: far more than a dynamometer shows in its band

json pairs_json(const std::vector<forcerec::RootPair>& pairs) {
  json a = json::array();
  for (const auto& p : pairs) a.push_back({{"fn_hz", p.fn_hz}, {"zeta", p.zeta}});
  return a;
}

std::string axis_name(char a) { return std::string(1, a); }

}  // namespace

std::vector<std::string> DynoFrfKind::keys() const { return {"axis", "hits", "band_hz", "order"}; }

std::shared_ptr<const KindSpec> DynoFrfKind::parse(const YAML::Node& root, YamlReader& r) const {
  auto s = std::make_shared<DynoFrfSpec>();
  const std::string axis = r.required_string(root, "axis");
  if (axis == "x" || axis == "y" || axis == "z") {
    s->axis = axis[0];
  } else if (root["axis"]) {
    r.error("axis", "must be x, y or z, not '" + axis + "'");
  }
  s->hits = read_hammer_hits(root, r);
  if (auto band = read_interval(root, r, "band_hz", false)) {
    s->band_given = true;
    s->band_lo_hz = band->first;
    s->band_hi_hz = band->second;
  }
  if (auto n = r.optional_int(root, "order", "", 2, kMaxOrder)) {
    if (*n % 2 != 0) {
      r.error("order", "must be even (one pole pair per mode), not " + std::to_string(*n));
    } else {
      s->order = static_cast<int>(*n);
    }
  }
  return s;
}

std::vector<std::string> DynoFrfKind::required_channels(const TestSpec&) const {
  return {"hammer", "dyno"};
}

std::vector<std::string> DynoFrfKind::check_record(const TestSpec& t, double duration_s) const {
  const auto& s = t.kind_spec<DynoFrfSpec>();
  std::vector<std::string> e = hammer_hits_outside(t, s.hits, duration_s);
  if (s.band_given && s.band_hi_hz > 0.5 * t.sample_rate_hz) {
    e.push_back(t.yaml_label + ": key 'band_hz' ends at " + fmt_sig(s.band_hi_hz, 6) +
                " Hz, above the Nyquist frequency (" + fmt_sig(0.5 * t.sample_rate_hz, 6) + " Hz)");
  }
  if (!s.band_given && kDefaultBandHiFraction * t.sample_rate_hz <= kDefaultBandLoHz) {
    e.push_back(t.yaml_label + ": key 'band_hz' is required at sample_rate_hz " +
                fmt_sig(t.sample_rate_hz, 6) +
                ": the default band [50, 0.4 sample_rate_hz] Hz is " + "empty below 125 Hz");
  }
  return e;
}

std::vector<std::string> DynoFrfKind::provides(const TestSpec& t) const {
  return {value::dyno_model(t.id), value::dyno_axis(t.kind_spec<DynoFrfSpec>().axis)};
}

std::string DynoFrfKind::describe_value(const std::string& name) const {
  if (name.rfind("dyno-model:", 0) == 0) return "the dynamometer model of " + name.substr(11);
  if (name.rfind("dyno-axis:", 0) == 0) return "a dynamometer model of axis " + name.substr(10);
  return "";
}

void DynoFrfKind::run(const TestSpec& t, const CampaignValues&, const RunContext&,
                      TestOutcome& out) const {
  const auto& s = t.kind_spec<DynoFrfSpec>();
  const std::string label = t.data_label();
  const SignalTable table = SignalTable::open(t.data, label);
  const Eigen::VectorXd hammer = table.channel("hammer", t.channel("hammer"));
  const Eigen::VectorXd dyno = table.channel("dyno", t.channel("dyno"));
  const double fs = t.sample_rate_hz;
  const std::vector<sifs::TapWindow> windows =
      hammer_windows(t, s.hits, hammer, label, out.warnings);
  auto res = std::make_unique<DynoFrfResult>();
  try {
    res->frf = sifs::tap_frf(hammer, dyno, fs, windows);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": " + e.what());
  }
  if (!res->frf.summary.ok()) {
    out.status.fail(label + ": " + res->frf.summary.message);
    return;
  }
  res->band_lo_hz = s.band_given ? s.band_lo_hz : kDefaultBandLoHz;
  res->band_hi_hz =
      s.band_given ? s.band_hi_hz : std::min(kDefaultBandHiHz, kDefaultBandHiFraction * fs);
  forcerec::TransferFitOptions o;
  o.order = s.order;
  o.band_lo_hz = res->band_lo_hz;
  o.band_hi_hz = res->band_hi_hz;
  try {
    res->fit = forcerec::fit_transfer_function(res->frf.f_hz, res->frf.h1, o);
  } catch (const InputError& e) {
    throw InputError(t.yaml_label + ": keys 'band_hz', 'order': " + e.what());
  }
  const auto& fit = res->fit;
  out.warnings.insert(out.warnings.end(), fit.summary.warnings.begin(), fit.summary.warnings.end());
  if (!fit.summary.ok()) {
    out.status.fail(label + ": transfer-function fit: " + fit.summary.message);
    return;
  }
  if (res->frf.hits < 2) {
    out.warnings.push_back("one hit: the coherence is 1 by construction");
  }
  auto m = std::make_shared<DynoModel>();
  m->id = t.id;
  m->axis = s.axis;
  m->model = fit.model;
  m->realization = fit.realization;
  m->fit_pct = fit.fit_pct;
  res->model = std::move(m);
  out.result = std::move(res);
  out.status.succeed();
}

template <class Ar>
void fields(Ar& ar, DynoFrfResult& r) {
  LAYOUT_GUARD(DynoFrfResult, 632);
  ar(r.frf, r.fit, r.band_lo_hz, r.band_hi_hz, r.model);
}

std::string DynoFrfKind::save(const TestOutcome& out) const {
  return save_result<DynoFrfResult>(out);
}

void DynoFrfKind::restore(const TestSpec&, const std::string& bytes, TestOutcome& out) const {
  restore_result<DynoFrfResult>(bytes, out);
}

void DynoFrfKind::publish(const TestOutcome& out, CampaignValues& values) const {
  const auto& m = out.result_of<DynoFrfResult>().model;
  values.put(value::dyno_model(out.spec->id), out.spec->id, m);
  values.put(value::dyno_axis(m->axis), out.spec->id, m);
}

json DynoFrfKind::results(const TestOutcome& out) const {
  const auto& r = out.result_of<DynoFrfResult>();
  const auto& s = out.spec->kind_spec<DynoFrfSpec>();
  const auto& f = r.fit;
  return {{"axis", axis_name(s.axis)},
          {"order", s.order},
          {"band_hz", {r.band_lo_hz, r.band_hi_hz}},
          {"hits_used", r.frf.hits},
          {"num", number_array(f.num)},
          {"den", number_array(f.den)},
          {"poles", pairs_json(f.model.pole_pairs)},
          {"real_poles_rad_s", f.model.real_poles_rad_s},
          {"zeros", pairs_json(f.model.zero_pairs)},
          {"real_zeros_rad_s", f.model.real_zeros_rad_s},
          {"gain_1_s", f.model.b1},
          {"dc_gain", f.dc_gain},
          {"fit_pct", f.fit_pct},
          {"band_points", f.f_hz.size()},
          {"zeros_mirrored", f.zeros_mirrored},
          {"realization_cond_A", f.realization_cond_A},
          {"frequency_resolution_hz", r.frf.df_hz}};
}

std::string DynoFrfKind::note(const TestOutcome& out) const {
  const auto& r = out.result_of<DynoFrfResult>();
  return "axis " + axis_name(out.spec->kind_spec<DynoFrfSpec>().axis) + ", order " +
         std::to_string(r.fit.model.order()) + ", fit " + fmt_sig(r.fit.fit_pct, 3) + " %";
}

render::Figure dyno_frf_figure(const DynoFrfResult& r) {
  const auto& f = r.frf;
  FrfFigureData d;
  // The band and a little around it: the model is meant for the band only.
  const double lo = 0.5 * r.band_lo_hz, hi = 1.25 * r.band_hi_hz;
  for (Eigen::Index i = 0; i < f.f_hz.size(); ++i) {
    const double fr = f.f_hz(i);
    if (fr < lo || fr > hi) continue;
    const std::complex<double> g = forcerec::transfer_response(r.fit.model, fr);
    d.f_hz.push_back(fr);
    d.measured_mag.push_back(std::abs(f.h1(i)));
    d.model_mag.push_back(std::abs(g));
    d.measured_phase_deg.push_back(std::arg(f.h1(i)) * kRadToDeg);
    d.model_phase_deg.push_back(std::arg(g) * kRadToDeg);
    d.coherence.push_back(f.coherence(i));
  }
  return frf_model_figure(d, {"|H| [N/N]", "H1 (hits)", "fit, eq. 3.1", ""});
}

void DynoFrfKind::figures(const CampaignResults&, const TestOutcome& out, FigureJobs& jobs) const {
  jobs.add(out.spec->id, "frf", figure_stem("dyno-frf", out.spec->id) + "frf",
           dyno_frf_figure(out.result_of<DynoFrfResult>()));
}

json DynoFrfKind::report_section(const CampaignResults&, const std::vector<const TestOutcome*>& ok,
                                 const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json tests = json::array();
  for (const TestOutcome* t : ok) {
    const auto& r = t->result_of<DynoFrfResult>();
    const auto& f = r.fit;
    json j;
    j["id"] = t->spec->id;
    j["axis"] = axis_name(t->spec->kind_spec<DynoFrfSpec>().axis);
    j["hits"] = r.frf.hits;
    j["order"] = f.model.order();
    j["band"] = fmt_sig(r.band_lo_hz, 4) + "&ndash;" + fmt_sig(r.band_hi_hz, 4);
    json roots = json::array();
    for (const auto& p : f.model.pole_pairs) {
      roots.push_back({{"what", "pole pair"},
                       {"fn_hz", fmt_sig(p.fn_hz, 5)},
                       {"zeta_pct", fmt_sig(p.zeta * 100, 3)}});
    }
    for (double p : f.model.real_poles_rad_s) {
      roots.push_back({{"what", "real pole"},
                       {"fn_hz", fmt_sig(std::abs(p) / kTwoPi, 5)},
                       {"zeta_pct", "100"}});
    }
    for (const auto& z : f.model.zero_pairs) {
      roots.push_back({{"what", "zero pair"},
                       {"fn_hz", fmt_sig(z.fn_hz, 5)},
                       {"zeta_pct", fmt_sig(z.zeta * 100, 3)}});
    }
    for (double z : f.model.real_zeros_rad_s) {
      roots.push_back({{"what", "real zero"},
                       {"fn_hz", fmt_sig(std::abs(z) / kTwoPi, 5)},
                       {"zeta_pct", z < 0 ? "100" : "-100"}});
    }
    j["roots"] = roots;
    j["dc_gain"] = fmt_sig(f.dc_gain, 5);
    j["gain_1_s"] = fmt_sig(f.model.b1, 4);
    j["fit_pct"] = fmt_sig(f.fit_pct, 3);
    j["cond_A"] = fmt_sig(f.realization_cond_A, 3);
    j["points"] = f.f_hz.size();
    j["df_hz"] = fmt_sig(r.frf.df_hz, 3);
    j["figure"] = figures.of(t->spec->id, "frf");
    j["has_warnings"] = !t->warnings.empty();
    j["warnings"] = t->warnings;
    tests.push_back(j);
  }
  return {{"toc", json::array({{{"anchor", "dyno-frf"}, {"title", "Dynamometer models"}}})},
          {"dyno_frfs", tests}};
}

void DynoFrfKind::compare_truth(const TruthInput& in, const TestOutcome& out,
                                TruthComparison& c) const {
  const auto& f = out.result_of<DynoFrfResult>().fit;
  const YAML::Node& v = *in.entry;
  const std::string& id = out.spec->id;
  // Truth pairs matched to fitted ones by nearest natural frequency.
  auto pairs = [&](const char* key, const std::vector<forcerec::RootPair>& fitted,
                   const std::string& prefix) {
    const YAML::Node list = v[key];
    if (!list || !list.IsSequence()) return;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const double fn = truth_number(list[i], "fn_hz");
      if (!std::isfinite(fn) || fitted.empty()) continue;
      const forcerec::RootPair* best = &fitted.front();
      for (const auto& p : fitted) {
        if (std::abs(p.fn_hz - fn) < std::abs(best->fn_hz - fn)) best = &p;
      }
      const std::string q = prefix + std::to_string(i + 1) + ".";
      add_truth_row(c, q + "fn_hz", id, fn, best->fn_hz);
      add_truth_row(c, q + "zeta", id, truth_number(list[i], "zeta"), best->zeta);
    }
  };
  pairs("modes", f.model.pole_pairs, "pole");
  pairs("zeros", f.model.zero_pairs, "zero");
  add_truth_row(c, "dc_gain", id, truth_number(v, "dc_gain"), f.dc_gain);
  add_truth_row(c, "gain_1_s", id, truth_number(v, "gain_1_s"), f.model.b1);
}

}  // namespace chatterlab::app
