// The report section of the cut tests (templates/kinds/cut.html): processing, offset,
// measured bifurcation, identification passes and values, the variants' table (000 table 5.2
// layout) and the campaign's estimator comparison.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "app/core/format.h"
#include "app/kinds/cut/cut_kind.h"
#include "app/report/figure_jobs.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

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

// A 95 % interval as the tables show it: "[lo, hi]" in the value's format, `unbounded` when an
// end is infinite (a near-singular direction).
std::string interval_text(double lo, double hi, const std::function<std::string(double)>& text,
                          const char* unbounded) {
  if (std::isfinite(lo) && std::isfinite(hi)) return "[" + text(lo) + ", " + text(hi) + "]";
  return unbounded;
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

// The joint estimate beside the sequence: one row per value of keyed_intervals, its 95 % interval
// and whether the cut identifies it; k, held, last. Empty when the joint fit did not succeed.
json joint_rows(const CutEstimation& e) {
  json rows = json::array();
  if (!e.joint.summary.ok()) return rows;
  std::map<std::string, double> sequence = sequence_values(e);
  sequence["offset_deg"] = e.offset.search.offset_angle_deg;
  auto text = [](const std::string& key, double v) {
    return key == "offset_deg" ? fmt_fixed(v, 3) : key_value(key, v);
  };
  for (const auto& keyed : keyed_intervals(e.joint)) {
    const std::string& key = keyed.first;
    const auto& iv = keyed.second;
    const std::string label = key == "offset_deg" ? "Offset angle (deg)" : key_format(key).label;
    const auto as_key = [&](double v) { return text(key, v); };
    rows.push_back({{"label", label},
                    {"sequence", text(key, sequence[key])},
                    {"joint", text(key, iv->value)},
                    {"interval", interval_text(iv->lo, iv->hi, as_key, "unbounded")},
                    {"identifiable", iv->identifiable}});
  }
  rows.push_back({{"label", key_format("k_N_m").label},
                  {"sequence", key_value("k_N_m", e.modal.k_N_m)},
                  {"joint", key_value("k_N_m", e.joint.k_N_m)},
                  {"interval", "held (scale)"},
                  {"identifiable", false},
                  {"held", true}});
  return rows;
}

// The rows of one cut test's variants (000 table 5.2 layout): one row per estimate key, the
// variant's own cells spanning its keys; a failed variant is one row with its message.
// Repeatability spread: sample standard deviation / |mean| of the seeded starts' finals.
json variant_rows(const CutEstimation& e) {
  json rows = json::array();
  for (const auto& v : e.variants) {
    const estimate::EkfResult& run = v.run;
    if (!run.summary.ok() || run.estimates.empty()) {
      rows.push_back(
          {{"variant", run.estimator},
           {"first", true},
           {"span", 1},
           {"failed", true},
           {"message", run.summary.ok() ? std::string("no estimates") : run.summary.message}});
      continue;
    }
    const estimate::RepeatabilityResult& rep = v.repeat;
    const std::string rank =
        v.observability_status.ok()
            ? std::to_string(v.observability.rank) + " of " + std::to_string(v.observability.states)
            : std::string("n/a");
    std::string steps = std::to_string(run.steps);
    if (run.filters > 1) steps += " (" + std::to_string(run.filters) + " filters)";
    for (std::size_t k = 0; k < run.estimates.size(); ++k) {
      const auto& est = run.estimates[k];
      std::string spread = rep.summary.ok()     ? std::string("n/a")
                           : !rep.summary.ran() ? std::string("not run")
                                                : std::string("failed");
      if (rep.summary.ok()) {
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
                  {"nis", fmt_sig(run.nis.mean, 3) + " [" + fmt_sig(run.nis.mean_band.lower, 3) +
                              ", " + fmt_sig(run.nis.mean_band.upper, 3) + "]"},
                  {"steps", steps},
                  {"runtime_s", fmt_sig(run.runtime_s, 3)}};
      if (k == 0 && !rep.summary.ok() && rep.summary.ran()) {
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
  j["measured"] = c.bifurcation_status.ok()
                      ? depth_text(c.bifurcation.bifurcation_depth_m, c.bifurcation.verdict)
                      : "not determined: " + c.bifurcation_status.message;
  j["traditional"] = j["numerical"] =
      c.estimation.summary.ok() ? "not simulated" : "not simulated (identification not available)";
  if (!c.estimation.summary.ok()) return j;
  for (const auto& s : c.estimation.simulated) {
    if (s.chip_model != "traditional" && s.chip_model != "numerical") continue;
    j[s.chip_model] =
        s.status.ok() ? depth_text(s.depth_m, s.verdict) : "simulation failed: " + s.status.message;
  }
  return j;
}

json cut_context(const CampaignResults& r, const TestOutcome& t, const FigureSet& figures) {
  const CutOutcome& c = t.result_of<CutOutcome>();
  const CutSpec& spec = t.spec->kind_spec<CutSpec>();
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
  const auto fig = [&](const std::string& key) { return figures.of(t.spec->id, key); };
  j["fig_processing"] = fig("processing");
  j["offset_ok"] = c.offset_status.ok();
  j["offset_message"] = c.offset_status.message;
  if (c.offset_status.ok()) {
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
  j["bifurcation_ok"] = c.bifurcation_status.ok();
  j["bifurcation_message"] = c.bifurcation_status.message;
  if (c.ramped && c.bifurcation_status.ok()) {
    const auto& b = c.bifurcation;
    j["bifurcation"] = b.bifurcation_depth_m
                           ? fmt_fixed(*b.bifurcation_depth_m * 1e3, 2) + " mm"
                           : std::string("none (") + dynamics::to_string(b.verdict) + ")";
    j["noise_floor_um"] = fmt_sig(b.noise_floor_m * 1e6, 3);
    j["fig_bifurcation"] = fig("bifurcation");
    const std::string p = fig("poincare");
    if (!p.empty()) j["fig_poincare"] = p;
  }
  j["orbit_ok"] = !c.ramped && c.orbit_status.ok();
  j["orbit_message"] = c.orbit_status.message;
  if (!c.ramped && c.orbit_status.ok()) {
    j["orbit"] = dynamics::to_string(c.orbit.shape);
    j["orbit_state"] = c.orbit.shape == dynamics::OrbitShape::kFixedPoint ? "stable" : "chatter";
    j["orbit_noise_floor_um"] = fmt_sig(c.orbit_noise_floor_m * 1e6, 3);
    const std::string p = fig("poincare");
    if (!p.empty()) j["fig_orbit"] = p;
  }
  // Identification and estimators (000 sec. 5.1, ch. 4 and 6): only from a sequence that
  // finished; otherwise its message and no number from it.
  const CutEstimation& e = c.estimation;
  j["est_ok"] = e.summary.ok();
  j["est_message"] = e.summary.message;
  if (e.summary.ok()) {
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
    est["joint_rows"] = joint_rows(e);
    est["joint_ok"] = e.joint.summary.ok();
    est["joint_message"] = e.joint.summary.ok() ? std::string() : e.joint.summary.message;
    est["joint_iterations"] = e.joint.iterations;
    est["joint_runtime_s"] = fmt_sig(e.joint.runtime_s, 3);
    est["joint_relative_pct"] = fmt_sig(100 * e.joint.relative_error, 3);
    est["joint_inflation"] = fmt_sig(e.joint.variance_inflation, 3);
    est["joint_warnings"] = e.joint.summary.warnings;
    est["offset_deg"] = fmt_fixed(e.offset.search.offset_angle_deg, 2);
    est["offset_relative_pct"] = fmt_sig(100 * e.offset.relative_error, 3);
    est["offset_hammer_deg"] = fmt_fixed(c.offset.search.offset_angle_deg, 2);
    est["offset_hammer_relative_pct"] = fmt_sig(100 * c.offset.relative_error, 3);
    est["variant_rows"] = variant_rows(e);
    json feedback = json::array();
    for (const auto& f : feedback_differences(e)) {
      feedback.push_back({{"key", key_format(f.key).label},
                          {"measured", key_value(f.key, f.measured)},
                          {"feedback", key_value(f.key, f.feedback)},
                          {"difference_pct", fmt_sig(f.difference_pct, 3)}});
    }
    est["has_feedback"] = !feedback.empty();
    est["feedback"] = feedback;
    est["has_seeded"] = estimation_options(r.campaign).repeat.runs > 0;
    est["seeded_runs"] = estimation_options(r.campaign).repeat.runs;
    est["seeded_spread_pct"] = fmt_sig(100 * estimation_options(r.campaign).repeat.spread, 3);
    json variant_figures = json::array();
    for (const auto& v : e.variants) {
      const std::string f = v.run.summary.ok() ? fig("estimator:" + v.run.estimator) : "";
      if (f.empty()) continue;
      variant_figures.push_back({{"variant", v.run.estimator},
                                 {"figure", f},
                                 {"known", v.known},
                                 {"start", v.start},
                                 {"seeded", v.repeat.summary.ok()}});
    }
    est["variant_figures_count"] = variant_figures.size();
    est["has_variant_figures"] = !variant_figures.empty();
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
    if (!t.status.ok() || t.spec->kind != "cut") continue;
    const CutOutcome& c = t.result_of<CutOutcome>();
    if (c.ramped) {
      json b = bifurcation_comparison(c);
      b["id"] = t.spec->id;
      bifurcations.push_back(b);
    }
    if (!c.estimation.summary.ok()) continue;
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
    const IdentifiedSet set = identified_set(src->result_of<CutOutcome>().estimation);
    j["identified_from"] = src->spec->id;
    j["identified_method"] = set.method == "joint" ? "the joint estimate, with 95 % intervals"
                                                   : "the identification sequence (the joint "
                                                     "estimate did not succeed: no intervals)";
    json rows_identified = json::array();
    for (const auto& v : set.values) {
      const bool interval = !std::isnan(v.lo) || !std::isnan(v.hi);
      const auto as_key = [&](double x) { return key_value(v.key, x); };
      rows_identified.push_back(
          {{"label", key_format(v.key).label},
           {"value", key_value(v.key, v.value)},
           {"interval",
            interval
                ? interval_text(v.lo, v.hi, as_key, "unbounded (not identifiable)")
                : std::string(v.key == "k_N_m" && set.method == "joint" ? "held (scale)" : "")}});
    }
    j["identified"] = rows_identified;
  }
  return j;
}

}  // namespace

std::string CutKind::note(const TestOutcome& t) const {
  const CutOutcome& c = t.result_of<CutOutcome>();
  std::string s = c.offset_status.ok()
                      ? "offset " + fmt_fixed(c.offset.search.offset_angle_deg, 2) + " deg"
                      : std::string("offset not determined");
  if (c.ramped && c.bifurcation_status.ok() && c.bifurcation.bifurcation_depth_m) {
    s += ", bifurcation " + fmt_fixed(*c.bifurcation.bifurcation_depth_m * 1e3, 2) + " mm";
  }
  // The offset found again with the identified values beside the hammer/dyno one.
  const CutEstimation& e = c.estimation;
  if (e.summary.ok()) {
    s += ", identified (offset " + fmt_fixed(e.offset.search.offset_angle_deg, 2) + " deg)";
  } else if (e.summary.ran()) {
    s += ", not identified";
  }
  return s;
}

json CutKind::report_section(const CampaignResults& r, const std::vector<const TestOutcome*>& ok,
                             const FigureSet& figures) const {
  if (ok.empty()) return nullptr;
  json cuts = json::array();
  for (const TestOutcome* t : ok) cuts.push_back(cut_context(r, *t, figures));
  json section;
  section["cut_tests"] = cuts;
  section["estimators"] = estimators_context(r);
  const CutStepInputs in = cut_inputs(r.campaign, r.values);
  section["cut_model"] =
      in.hammer_x && in.coefficients
          ? "the hammer-test modal parameters (" + in.hammer_source +
                ", the mode of largest peak receptance) and the dynamometer coefficients "
                "(Ktc, Krc of every tooth)"
          : std::string("the hammer-test and dynamometer values (none available in this campaign)");
  json toc = json::array({{{"anchor", "cuts"}, {"title", "Cut runs"}}});
  if (section["estimators"]["present"].get<bool>()) {
    toc.push_back({{"anchor", "estimators"}, {"title", "Estimator comparison"}});
  }
  section["toc"] = toc;
  return section;
}

}  // namespace chatterlab::app
