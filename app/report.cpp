#include "app/report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <fstream>
#include <future>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "app/document.h"
#include "app/format.h"
#include "app/report_figures.h"
#include "app/results_json.h"
#include "app/truth.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr double kRadToDeg = 57.29577951308232;

std::string kind_note(const TestOutcome& t) {
  if (!t.status.ok) return "";
  if (t.tap) {
    if (!t.tap->fit_ok) return "FRF only; fit failed";
    std::string s = std::to_string(t.tap->modes.size()) + " mode(s), first at " +
                    fmt_sig(t.tap->modes.front().fn_hz, 4) + " Hz";
    return s;
  }
  if (t.cut) {
    std::string s = t.cut->offset_status.ok
                        ? "offset " + fmt_fixed(t.cut->offset.search.offset_angle_deg, 2) + " deg"
                        : std::string("offset not determined");
    if (t.cut->ramped && t.cut->bifurcation_status.ok && t.cut->bifurcation.bifurcation_depth_m) {
      s += ", bifurcation " + fmt_fixed(*t.cut->bifurcation.bifurcation_depth_m * 1e3, 2) + " mm";
    }
    // The offset found again with the identified values beside the hammer/dyno one.
    const CutEstimation& e = t.cut->estimation;
    if (e.summary.ok) {
      s += ", identified (offset " + fmt_fixed(e.offset.search.offset_angle_deg, 2) + " deg)";
    } else if (e.summary.message != "not run") {
      s += ", not identified";
    }
    return s;
  }
  if (t.dyno) return "theta_dyn " + fmt_fixed(t.dyno->result.theta_dyn_rad * kRadToDeg, 2) + " deg";
  return "";
}

json tap_context(const TestOutcome& t, const std::string& figure) {
  const TapOutcome& tap = *t.tap;
  json j;
  j["id"] = t.spec->id;
  j["axis"] = t.spec->tap->axis;
  j["response"] = t.spec->tap->response;
  j["hits_used"] = tap.hits_used;
  j["hits_total"] = tap.hits.size();
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

// An estimate key (EXPERIMENT_FORMAT.md) as a table heading, HTML for {{{ }}}, and the factor
// its values are divided by: "m_kg" -> "m (kg)", "Kt1_N_m2" -> "K<sub>t1</sub> (10^8 N/m^2)"
// (coefficients in 10^8 N/m^2 as in the dynamometer table).
struct KeyFormat {
  std::string label;
  double scale = 1.0;
};
KeyFormat key_format(const std::string& key) {
  const auto u = key.find('_');
  const std::string sym = key.substr(0, u);
  const std::string unit = u == std::string::npos ? std::string() : key.substr(u + 1);
  if (unit == "N_m2" && sym.size() > 1) {
    return {sym.substr(0, 1) + "<sub>" + sym.substr(1) + "</sub> (10<sup>8</sup> N/m&sup2;)", 1e8};
  }
  if (unit == "kg") return {sym + " (kg)", 1.0};
  if (unit == "kg_s") return {sym + " (kg/s)", 1.0};
  if (unit == "N_m") return {sym + " (N/m)", 1.0};
  if (key == "fn_hz") return {"f<sub>n</sub> = &radic;(k/m) / 2&pi; (Hz), scale-free", 1.0};
  if (key == "zeta") return {"&zeta; = c / 2&radic;(km) (%), scale-free", 0.01};
  if (unit == "over_k_per_m" && sym.size() > 1) {
    return {sym.substr(0, 1) + "<sub>" + sym.substr(1) + "</sub> / k (1/m), scale-free", 1.0};
  }
  return {key, 1.0};
}

std::string key_value(const std::string& key, double v) {
  return fmt_sig(v / key_format(key).scale, 4);
}

json identified_rows(const CutEstimation& e) {
  json rows = json::array();
  for (const auto& [key, v] : keyed_values(e.modal, e.coefficients)) {
    rows.push_back({{"label", key_format(key).label}, {"value", key_value(key, v)}});
  }
  for (const auto& [key, v] : scale_free_values(e)) {
    rows.push_back({{"label", key_format(key).label}, {"value", key_value(key, v)}});
  }
  return rows;
}

// The rows of one cut test's variants (000 table 5.2 layout): one row per estimate key, the
// variant's own cells spanning its keys; a failed variant is one row with its message.
// Repeatability spread: sample standard deviation / |mean| of the seeded starts' finals.
json variant_rows(const CutEstimation& e) {
  json rows = json::array();
  for (const auto& v : e.variants) {
    const estimate::EkfResult& run = v.run;
    if (!run.summary.ok || run.estimates.empty()) {
      rows.push_back(
          {{"variant", run.estimator},
           {"first", true},
           {"span", 1},
           {"failed", true},
           {"message", run.summary.ok ? std::string("no estimates") : run.summary.message}});
      continue;
    }
    const estimate::RepeatabilityResult& rep = v.repeat;
    const std::string rank =
        v.observability_status.ok
            ? std::to_string(v.observability.rank) + " of " + std::to_string(v.observability.states)
            : std::string("n/a");
    std::string steps = std::to_string(run.steps);
    if (run.filters > 1) steps += " (" + std::to_string(run.filters) + " filters)";
    for (std::size_t k = 0; k < run.estimates.size(); ++k) {
      const auto& est = run.estimates[k];
      std::string spread = rep.summary.ok                     ? std::string("n/a")
                           : rep.summary.message == "not run" ? std::string("not run")
                                                              : std::string("failed");
      if (rep.summary.ok) {
        const auto it = std::find(rep.keys.begin(), rep.keys.end(), est.key);
        const auto i = static_cast<Eigen::Index>(it - rep.keys.begin());
        if (it != rep.keys.end() && i < rep.mean.size() && i < rep.std_dev.size()) {
          spread = fmt_sig(100.0 * rep.std_dev[i] / std::abs(rep.mean[i]), 2);
        }
      }
      json row = {{"variant", run.estimator},
                  {"first", k == 0},
                  {"span", run.estimates.size()},
                  {"failed", false},
                  {"key", key_format(est.key).label},
                  {"final", key_value(est.key, est.value)},
                  {"spread", spread},
                  {"rank", rank},
                  {"steps", steps},
                  {"runtime_s", fmt_sig(run.runtime_s, 3)}};
      if (k == 0 && !rep.summary.ok && rep.summary.message != "not run") {
        row["spread_message"] = rep.summary.message;
      }
      rows.push_back(row);
    }
  }
  return rows;
}

std::string depth_text(const std::optional<double>& depth_m, dynamics::RunVerdict verdict) {
  return depth_m ? fmt_fixed(*depth_m * 1e3, 2)
                 : std::string("none (") + dynamics::to_string(verdict) + ")";
}

// Measured against simulated bifurcation depth of a ramped cut (000 table 5.1), mm.
json bifurcation_comparison(const CutOutcome& c) {
  json j;
  j["measured"] = c.bifurcation_status.ok
                      ? depth_text(c.bifurcation.bifurcation_depth_m, c.bifurcation.verdict)
                      : "not determined: " + c.bifurcation_status.message;
  j["traditional"] = j["numerical"] =
      c.estimation.summary.ok ? "not simulated" : "not simulated (identification not available)";
  if (!c.estimation.summary.ok) return j;
  for (const auto& s : c.estimation.simulated) {
    if (s.chip_model != "traditional" && s.chip_model != "numerical") continue;
    j[s.chip_model] =
        s.status.ok ? depth_text(s.depth_m, s.verdict) : "simulation failed: " + s.status.message;
  }
  return j;
}

json cut_context(const CampaignResults& r, const TestOutcome& t, const FigureSet& figures) {
  const CutOutcome& c = *t.cut;
  const auto& spec = *t.spec->cut;
  json j;
  j["id"] = t.spec->id;
  std::string depth = fmt_sig(spec.axial_depth_m.first * 1e3, 3) + " mm";
  if (spec.axial_depth_m.first != spec.axial_depth_m.second) {
    depth += " to " + fmt_sig(spec.axial_depth_m.second * 1e3, 3) + " mm";
  }
  j["conditions"] = spec.operation + ", " + fmt_sig(spec.spindle_rpm, 5) + " rpm, depth " + depth;
  j["tach_revolutions"] = c.tach.revolutions;
  j["measured_rpm"] = fmt_sig(c.tach.measured_rpm, 6);
  j["air_revolutions"] = c.air_revolutions;
  j["has_warnings"] = !t.warnings.empty();
  j["warnings"] = t.warnings;
  const auto it = figures.cut.find(t.spec->id);
  const auto fig = [&](const char* kind) {
    if (it == figures.cut.end()) return std::string();
    const auto k = it->second.find(kind);
    return k == it->second.end() ? std::string() : k->second;
  };
  j["fig_processing"] = fig("processing");
  j["offset_ok"] = c.offset_status.ok;
  j["offset_message"] = c.offset_status.message;
  if (c.offset_status.ok) {
    const auto& s = c.offset.search;
    j["offset_deg"] = fmt_fixed(s.offset_angle_deg, 2);
    j["offset_error_um"] = fmt_sig(s.rms_error_m * 1e6, 3);
    j["offset_relative_pct"] = fmt_sig(100 * c.offset.relative_error, 3);
    j["runner_up_deg"] = fmt_fixed(s.runner_up_deg, 2);
    j["runner_up_ratio"] = fmt_fixed(s.runner_up_ratio, 3);
    j["offset_depth_mm"] = fmt_sig(c.offset.depth_m * 1e3, 3);
    j["fig_offset"] = fig("offset");
  }
  j["ramped"] = c.ramped;
  j["bifurcation_ok"] = c.bifurcation_status.ok;
  j["bifurcation_message"] = c.bifurcation_status.message;
  if (c.ramped && c.bifurcation_status.ok) {
    const auto& b = c.bifurcation;
    j["bifurcation"] = b.bifurcation_depth_m
                           ? fmt_fixed(*b.bifurcation_depth_m * 1e3, 2) + " mm"
                           : std::string("none (") + dynamics::to_string(b.verdict) + ")";
    j["noise_floor_um"] = fmt_sig(b.noise_floor_m * 1e6, 3);
    j["fig_bifurcation"] = fig("bifurcation");
    const std::string p = fig("poincare");
    if (!p.empty()) j["fig_poincare"] = p;
  }
  // Identification and estimators (000 sec. 5.1, ch. 4 and 6): only from a sequence that
  // finished; otherwise its message and no number from it.
  const CutEstimation& e = c.estimation;
  j["est_ok"] = e.summary.ok;
  j["est_message"] = e.summary.message;
  if (e.summary.ok) {
    json est;
    est["window_s"] = fmt_sig(e.window.start_s, 4) + "\u2013" + fmt_sig(e.window.end_s, 4);
    std::string depth_range = fmt_sig(e.window.depth_start_m * 1e3, 3);
    if (e.window.depth_end_m != e.window.depth_start_m) {
      depth_range += "\u2013" + fmt_sig(e.window.depth_end_m * 1e3, 3);
    }
    est["depth_mm"] = depth_range;
    est["rule"] = e.window.rule;
    est["resampled_samples"] = e.resampled_samples;
    est["passes_count"] = e.passes.size();
    est["converged"] = e.converged;
    est["runtime_s"] = fmt_sig(e.runtime_s, 3);
    json columns = json::array({"Offset used (deg)", "Offset found (deg)"});
    if (!e.passes.empty()) {
      for (const auto& [key, v] :
           keyed_values(e.passes.front().modal, e.passes.front().coefficients)) {
        columns.push_back(key_format(key).label);
      }
    }
    json passes = json::array();
    for (std::size_t i = 0; i < e.passes.size(); ++i) {
      const auto& p = e.passes[i];
      json cells = json::array({fmt_fixed(p.offset_deg, 2), fmt_fixed(p.offset_after_deg, 2)});
      for (const auto& [key, v] : keyed_values(p.modal, p.coefficients)) {
        cells.push_back(key_value(key, v));
      }
      passes.push_back({{"n", i + 1}, {"cells", cells}});
    }
    est["pass_columns"] = columns;
    est["passes"] = passes;
    est["identified"] = identified_rows(e);
    est["offset_deg"] = fmt_fixed(e.offset.search.offset_angle_deg, 2);
    est["offset_relative_pct"] = fmt_sig(100 * e.offset.relative_error, 3);
    est["offset_hammer_deg"] = fmt_fixed(c.offset.search.offset_angle_deg, 2);
    est["offset_hammer_relative_pct"] = fmt_sig(100 * c.offset.relative_error, 3);
    est["variant_rows"] = variant_rows(e);
    est["has_seeded"] = r.campaign.estimation.repeat.runs > 0;
    est["seeded_runs"] = r.campaign.estimation.repeat.runs;
    est["seeded_spread_pct"] = fmt_sig(100 * r.campaign.estimation.repeat.spread, 3);
    json variant_figures = json::array();
    for (const auto& v : e.variants) {
      const std::string f = v.run.summary.ok ? fig(("estimator:" + v.run.estimator).c_str()) : "";
      if (f.empty()) continue;
      variant_figures.push_back({{"variant", v.run.estimator},
                                 {"figure", f},
                                 {"known", v.known},
                                 {"start", v.start},
                                 {"seeded", v.repeat.summary.ok}});
    }
    est["variant_figures"] = variant_figures;
    if (c.ramped) est["bifurcation"] = bifurcation_comparison(c);
    const std::string chip = fig("chip");
    if (!chip.empty()) est["fig_chip"] = chip;
    j["est"] = est;
  }
  return j;
}

// The campaign's estimator comparison (000 table 5.2 across cut tests), its identified values
// and the measured against simulated bifurcation depths of the ramped cuts (000 table 5.1).
json estimators_context(const CampaignResults& r) {
  json j;
  json rows = json::array(), bifurcations = json::array();
  for (const auto& t : r.tests) {
    if (!t.status.ok || !t.cut) continue;
    const CutOutcome& c = *t.cut;
    if (c.ramped) {
      json b = bifurcation_comparison(c);
      b["id"] = t.spec->id;
      bifurcations.push_back(b);
    }
    if (!c.estimation.summary.ok) continue;
    json test_rows = variant_rows(c.estimation);
    for (std::size_t i = 0; i < test_rows.size(); ++i) {
      test_rows[i]["id"] = t.spec->id;
      test_rows[i]["test_first"] = i == 0;
      test_rows[i]["row_class"] = i == 0 ? "group test-group" : "group";
      test_rows[i]["test_span"] = test_rows.size();
      rows.push_back(test_rows[i]);
    }
  }
  j["present"] = !rows.empty();
  j["rows"] = rows;
  j["has_bifurcations"] = !bifurcations.empty();
  j["bifurcations"] = bifurcations;
  if (const TestOutcome* src = identification_source(r)) {
    j["identified_from"] = src->spec->id;
    j["identified"] = identified_rows(src->cut->estimation);
  }
  return j;
}

json dyno_context(const CampaignResults& r, const std::string& figure) {
  json d;
  json records = json::array();
  for (const auto& t : r.tests) {
    if (!t.dyno) continue;
    const auto& res = t.dyno->result;
    records.push_back({{"id", t.spec->id},
                       {"feed_mm", fmt_sig(t.dyno->feed_per_tooth_m * 1e3, 3)},
                       {"depth_mm", fmt_sig(t.dyno->axial_depth_m * 1e3, 3)},
                       {"rpm", fmt_sig(t.dyno->spindle_rpm, 5)},
                       {"revolutions", res.revolutions},
                       {"theta_dyn_deg", fmt_fixed(res.theta_dyn_rad * kRadToDeg, 2)},
                       {"mean_Ft_N", fmt_sig(res.mean_Ft_N, 4)},
                       {"mean_Fr_N", fmt_sig(res.mean_Fr_N, 4)}});
  }
  d["has_records"] = !records.empty();
  d["records"] = records;
  const auto& g = *r.dyno_group;
  d["fit_ok"] = g.summary.ok;
  d["fit_message"] = g.summary.message;
  d["figure"] = figure;
  const auto& k = g.fit.coefficients;
  d["Ktc_e8"] = fmt_fixed(k.Ktc_N_per_m2 / 1e8, 2);
  d["Kte_e3"] = fmt_sig(k.Kte_N_per_m / 1e3, 3);
  d["Krc_e8"] = fmt_fixed(k.Krc_N_per_m2 / 1e8, 2);
  d["Kre_e3"] = fmt_sig(k.Kre_N_per_m / 1e3, 3);
  d["rms_t_N"] = fmt_sig(g.fit.tangential.rms_residual_N, 3);
  d["rms_r_N"] = fmt_sig(g.fit.radial.rms_residual_N, 3);
  d["r2_t"] = fmt_fixed(g.fit.tangential.r_squared, 4);
  d["r2_r"] = fmt_fixed(g.fit.radial.r_squared, 4);
  std::string tool =
      r.campaign.workpiece.empty() ? std::string("workpiece not given") : r.campaign.workpiece;
  if (r.campaign.tool) {
    tool += " / " + std::to_string(r.campaign.tool->teeth) +
            "-tooth, r = " + fmt_sig(r.campaign.tool->radius_m * 1e3, 3) + " mm";
    if (r.campaign.tool->helix_deg)
      tool += ", " + fmt_sig(*r.campaign.tool->helix_deg, 3) + "-deg helix";
  }
  d["tool_label"] = tool;
  d["convention_note"] =
      g.fit.mean_force_model == cutting::SlotMeanForceModel::kSingleToothChip
          ? "Coefficients use mean |F| = (2/\u03c0) b K<sub>c</sub> h + b K<sub>e</sub>, which "
            "agrees "
            "with the force model of eqs 3.3\u20133.4 (one tooth cutting a chip h sin \u03b8 at a "
            "time); 000 eq. 3.5 as printed gives half these K<sub>tc</sub>, K<sub>rc</sub> "
            "(docs/dyno-coefficients.md)."
          : "Coefficients use 000 eqs 3.5 and 3.9\u20133.12 as printed (mean |F| = (4/\u03c0) b "
            "K<sub>c</sub> h + b K<sub>e</sub>); the force model of eqs 3.3\u20133.4 implies twice "
            "these K<sub>tc</sub>, K<sub>rc</sub> (docs/dyno-coefficients.md).";
  return d;
}

json setting(const std::string& key, const std::string& value) {
  return {{"key", key}, {"value", value}};
}

// The analysis settings in force (defaults unless changed), for the provenance section.
json settings_context(const PipelineOptions& p, const ReportOptions& r) {
  const auto& h = p.tap.hits;
  const auto& f = p.tap.frf;
  const auto& m = p.tap.fit;
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return json::array(
      {setting("tap: hit threshold", fmt_sig(100 * h.threshold_fraction, 3) +
                                         " % of the largest peak, at least " +
                                         fmt_sig(h.noise_multiple, 3) + " x force noise"),
       setting("tap: pre-trigger", fmt_sig(h.pretrigger_s * 1e3, 3) + " ms"),
       setting("tap: double-hit window", fmt_sig(h.double_hit_window_s * 1e3, 3) + " ms"),
       setting("tap: exponential window", f.exp_window_auto
                                              ? "automatic, response down to " +
                                                    fmt_sig(100 * f.exp_window_end_fraction, 2) +
                                                    " % at the record end"
                                              : "tau = " + fmt_sig(f.exp_window_tau_s, 3) + " s"),
       setting("tap: FRF estimator for the fit",
               m.estimator == frf::FrfEstimator::kH1 ? "H1" : "H2"),
       setting("tap: automatic band and modes",
               "peaks with coherence >= " + fmt_sig(m.min_coherence, 2) +
                   ", prominence >= " + fmt_sig(m.min_prominence_db, 2) +
                   " dB; band over peaks within " + fmt_sig(m.band_dominance_db, 2) +
                   " dB of the largest; modes within " + fmt_sig(m.mode_floor_db, 2) + " dB"),
       setting("tap: residual terms", m.residual_terms ? "upper and lower" : "none"),
       setting("dyno: mean-force model",
               p.dyno.mean_force_model == cutting::SlotMeanForceModel::kSingleToothChip
                   ? "single-tooth chip (2/pi), default"
                   : "000 eq. 3.5 as printed (4/pi)"),
       setting("dyno: zero-count threshold (when test.yaml gives none)",
               fmt_sig(p.dyno.zero_threshold_V, 3) + " V"),
       setting("dyno: pulse spacing tolerance", fmt_sig(100 * p.dyno.rpm_tolerance, 3) + " %"),
       setting("worker threads", r.jobs > 0
                                     ? std::to_string(r.jobs)
                                     : "one per hardware thread (" + std::to_string(hw) + ")")});
}

}  // namespace

int run_report(const std::filesystem::path& campaign_dir, const std::filesystem::path& out,
               const ReportOptions& options, std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  CampaignSpec spec = load_campaign(campaign_dir);
  if (!std::filesystem::exists(spec.root / "campaign.yaml") ||
      !std::filesystem::is_directory(spec.root)) {
    for (const auto& e : spec.errors) log << "chatterlab report: " << e << "\n";
    return 1;
  }
  PipelineOptions popt;
  popt.jobs = options.jobs;
  CampaignResults r = run_campaign(std::move(spec), popt);
  const TruthComparison truth = compare_with_truth(r);

  std::filesystem::create_directories(out / "figures");
  const FigureSet figures = render_report_figures(r, out, options.jobs);

  json ctx;
  const auto& c = r.campaign;
  ctx["campaign"] = {{"name", c.name.empty() ? c.root.filename().string() : c.name},
                     {"description", c.description},
                     {"workpiece", c.workpiece},
                     {"machine", c.machine},
                     {"root", c.root.string()}};
  if (c.tool) {
    json tool = {{"teeth", c.tool->teeth}, {"radius_mm", fmt_sig(c.tool->radius_m * 1e3, 4)}};
    if (c.tool->helix_deg) tool["helix_deg"] = fmt_sig(*c.tool->helix_deg, 3);
    ctx["campaign"]["tool"] = tool;
  }
  ctx["generated_utc"] = utc_timestamp();
  ctx["version"] = CHATTERLAB_VERSION;
  json tests = json::array(), skipped = json::array(), taps = json::array(), cuts = json::array();
  std::vector<std::string> warnings = c.errors;
  warnings.insert(warnings.end(), c.warnings.begin(), c.warnings.end());
  warnings.insert(warnings.end(), truth.warnings.begin(), truth.warnings.end());
  warnings.insert(warnings.end(), figures.errors.begin(), figures.errors.end());
  int ok = 0;
  for (const auto& t : r.tests) {
    const std::string id = t.spec->id.empty() ? "." : t.spec->id;
    tests.push_back({{"id", id},
                     {"kind", t.spec->kind.empty() ? "?" : t.spec->kind},
                     {"status", t.status.ok ? "ok" : "skipped"},
                     {"note", kind_note(t)}});
    if (t.status.ok) {
      ++ok;
    } else {
      skipped.push_back({{"id", id}, {"reason", t.status.message}});
    }
    if (t.status.ok && t.tap) taps.push_back(tap_context(t, figures.of(t.spec->id)));
    if (t.status.ok && t.cut) cuts.push_back(cut_context(r, t, figures));
    if (t.status.ok && !t.tap && !t.cut) {
      for (const auto& w : t.warnings) warnings.push_back(id + ": " + w);
    }
  }
  ctx["tests"] = tests;
  ctx["skipped"] = skipped;
  ctx["summary"] = {{"tests_found", r.tests.size()},
                    {"tests_ok", ok},
                    {"tests_skipped", r.tests.size() - static_cast<std::size_t>(ok)}};
  ctx["has_tap"] = !taps.empty();
  ctx["tap_tests"] = taps;
  ctx["has_dyno"] = r.dyno_group.has_value();
  ctx["has_cut"] = !cuts.empty();
  ctx["cut_tests"] = cuts;
  ctx["estimators"] = estimators_context(r);
  ctx["cut_model"] =
      r.cut_inputs.hammer_x && r.cut_inputs.coefficients
          ? "the hammer-test modal parameters (" + r.cut_inputs.hammer_source +
                ", the mode of largest peak receptance) and the dynamometer coefficients "
                "(Ktc, Krc of every tooth)"
          : std::string("the hammer-test and dynamometer values (none available in this campaign)");
  if (r.dyno_group) {
    ctx["dyno"] = dyno_context(r, figures.dyno);
    if (!r.dyno_group->summary.warnings.empty()) {
      for (const auto& w : r.dyno_group->summary.warnings)
        warnings.push_back("dyno-slot group: " + w);
    }
  }
  ctx["has_skipped"] = !skipped.empty();
  ctx["has_warnings"] = !warnings.empty();
  ctx["warnings"] = warnings;
  json truth_rows = json::array();
  for (const auto& row : truth.rows) {
    truth_rows.push_back({{"quantity", row.quantity},
                          {"source", row.source},
                          {"truth", fmt_sig(row.truth, 5)},
                          {"estimate", fmt_sig(row.estimate, 5)},
                          {"error_pct", fmt_fixed(row.error_pct, 2)}});
  }
  ctx["truth"] = {{"present", truth.present && !truth.rows.empty()}, {"rows", truth_rows}};
  json inputs = json::array();
  for (const auto& f : r.inputs) {
    inputs.push_back({{"file", f.relative_path}, {"bytes", f.bytes}, {"sha256", f.sha256}});
  }
  const double runtime =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ctx["provenance"] = {{"inputs", inputs},
                       {"runtime_s", fmt_sig(runtime, 3)},
                       {"settings", settings_context(popt, options)}};

  // results.json first: it must exist even if the PDF step fails.
  {
    std::ofstream js(out / "results.json");
    js << results_json(r, truth).dump(2) << "\n";
  }
  const bool pdf_written = write_documents("report.html", ctx, out, options.pdf, "report", log);
  const int rc = options.pdf && !pdf_written ? 1 : 0;
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "report: " << r.tests.size() << " tests, " << ok << " analysed, "
      << r.tests.size() - static_cast<std::size_t>(ok) << " skipped; wrote "
      << (out / "index.html").string() << (pdf_written ? ", report.pdf" : "")
      << ", results.json in " << fmt_sig(total, 3) << " s\n";
  for (const auto& s : skipped)
    log << "  skipped " << s["id"].get<std::string>() << ": " << s["reason"].get<std::string>()
        << "\n";
  return rc;
}

}  // namespace chatterlab::app
