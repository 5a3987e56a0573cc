#include "app/results_json.h"

#include <cmath>

namespace chatterlab::app {

using nlohmann::json;

namespace {

constexpr double kRadToDeg = 57.29577951308232;

json tap_json(const TapOutcome& t) {
  json j;
  j["hits_used"] = t.hits_used;
  json hits = json::array();
  for (const auto& h : t.hits) {
    json e = {{"time_s", h.time_s}, {"peak_force_N", h.peak_N}, {"accepted", h.accepted}};
    if (!h.accepted) e["rejected_because"] = h.reason;
    hits.push_back(e);
  }
  j["hits"] = hits;
  j["frequency_resolution_hz"] = number_or_null(t.df_hz);
  j["exp_window_tau_s"] = number_or_null(t.exp_window_tau_s);
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

json dyno_json(const DynoRecordOutcome& d) {
  const auto& r = d.result;
  return {{"feed_per_tooth_m", d.feed_per_tooth_m},
          {"axial_depth_m", d.axial_depth_m},
          {"spindle_rpm", d.spindle_rpm},
          {"measured_rpm", number_or_null(r.measured_rpm)},
          {"revolutions", r.revolutions},
          {"theta_dyn_deg", number_or_null(r.theta_dyn_rad * kRadToDeg)},
          {"mean_Ft_N", number_or_null(r.mean_Ft_N)},
          {"mean_Fr_N", number_or_null(r.mean_Fr_N)},
          {"spread_Ft_N", number_or_null(r.spread_Ft_N)},
          {"spread_Fr_N", number_or_null(r.spread_Fr_N)},
          {"offset_x_N", number_or_null(r.offset_x_N)},
          {"offset_y_N", number_or_null(r.offset_y_N)},
          {"switching_contrast", number_or_null(r.switching_contrast)}};
}

json values_json(const estimate::ModalParameters& m,
                 const std::vector<estimate::ToothCoefficients>& k) {
  json j = json::object();
  for (const auto& [key, v] : keyed_values(m, k)) j[key] = number_or_null(v);
  return j;
}

json identified_json(const CutEstimation& e) {
  json j = values_json(e.modal, e.coefficients);
  // The scale-free combinations that deflection data determine on their own
  // (docs/identification.md, "Scale").
  for (const auto& [k, v] : scale_free_values(e)) j[k] = number_or_null(v);
  return j;
}

json variant_json(const VariantOutcome& v) {
  const estimate::EkfResult& r = v.run;
  json j;
  if (!r.summary.ok) {
    j["status"] = "failed";
    j["message"] = r.summary.message;
    return j;
  }
  json est = json::object(), var = json::object();
  for (const auto& e : r.estimates) {
    est[e.key] = number_or_null(e.value);
    var[e.key] = number_or_null(e.variance);
  }
  j["estimates"] = est;
  j["final_variance"] = var;
  j["runtime_s"] = r.runtime_s;
  j["steps"] = r.steps;
  j["filters"] = r.filters;
  j["time_step_s"] = r.time_step_s;
  j["steps_per_s"] = r.runtime_s > 0 ? json(static_cast<double>(r.steps * r.filters) / r.runtime_s)
                                     : json(nullptr);
  j["known"] = v.known;
  j["start"] = v.start;
  if (v.observability_status.ok) {
    j["observability_rank"] = v.observability.rank;
    j["observability_states"] = v.observability.states;
  } else {
    j["observability_message"] = v.observability_status.message;
  }
  const estimate::RepeatabilityResult& rep = v.repeat;
  if (!rep.keys.empty()) {
    json rj;
    rj["runs"] = rep.initial.rows();
    rj["status"] = rep.summary.ok ? "ok" : "failed";
    if (!rep.summary.ok) rj["message"] = rep.summary.message;
    json mean = json::object(), sd = json::object(), lo = json::object(), hi = json::object(),
         rel = json::object();
    for (std::size_t k = 0; k < rep.keys.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      if (rep.mean.size() <= i) break;
      mean[rep.keys[k]] = number_or_null(rep.mean[i]);
      sd[rep.keys[k]] = number_or_null(rep.std_dev[i]);
      lo[rep.keys[k]] = number_or_null(rep.min[i]);
      hi[rep.keys[k]] = number_or_null(rep.max[i]);
      rel[rep.keys[k]] = number_or_null(100.0 * rep.std_dev[i] / std::abs(rep.mean[i]));
    }
    rj["mean"] = mean;
    rj["std_dev"] = sd;
    rj["min"] = lo;
    rj["max"] = hi;
    rj["std_dev_pct"] = rel;
    j["repeatability"] = rj;
  }
  return j;
}

json estimation_json(const CutEstimation& e) {
  json j;
  j["window_s"] = {e.window.start_s, e.window.end_s};
  j["window_depth_m"] = {e.window.depth_start_m, e.window.depth_end_m};
  j["window_rule"] = e.window.rule;
  j["resampled_samples"] = e.resampled_samples;
  json passes = json::array();
  for (const auto& p : e.passes) {
    json pj = values_json(p.modal, p.coefficients);
    pj["offset_used_deg"] = p.offset_deg;
    pj["offset_found_deg"] = p.offset_after_deg;
    pj["offset_relative_error"] = number_or_null(p.offset_relative_error);
    passes.push_back(pj);
  }
  j["passes"] = passes;
  j["converged"] = e.converged;
  j["identified"] = identified_json(e);
  j["runtime_s"] = e.runtime_s;
  return j;
}

// A cut test (EXPERIMENT_FORMAT.md: offset_angle_deg; bifurcation_depth_mm null when the run
// shows no bifurcation, absent when its depth does not vary). A step that did not succeed
// leaves its keys out and says why.
json cut_json(const CutOutcome& c) {
  json j;
  j["measured_rpm"] = number_or_null(c.tach.measured_rpm);
  j["tach_revolutions"] = c.tach.revolutions;
  j["air_revolutions"] = c.air_revolutions;
  const bool identified = c.estimation.summary.ok;
  if (c.offset_status.ok) {
    const auto& s = c.offset.search;
    // offset_angle_deg: found with the identified values when the identification ran, else
    // with the hammer-test and dynamometer values (docs/identification.md).
    j["offset_angle_deg"] =
        identified ? c.estimation.offset.search.offset_angle_deg : s.offset_angle_deg;
    j["offset_source"] = identified ? "identified" : "hammer-dyno";
    j["offset_hammer_dyno_deg"] = s.offset_angle_deg;
    j["offset_rms_error_m"] = s.rms_error_m;
    j["offset_relative_error"] = number_or_null(c.offset.relative_error);
    j["offset_runner_up_deg"] = number_or_null(s.runner_up_deg);
    j["offset_runner_up_ratio"] = number_or_null(s.runner_up_ratio);
    j["offset_ambiguous"] = s.ambiguous;
    j["offset_comparison_depth_m"] = c.offset.depth_m;
  } else {
    j["offset_status"] = "skipped";
    j["offset_skip_reason"] = c.offset_status.message;
  }
  if (c.ramped) {
    if (c.bifurcation_status.ok) {
      const auto& b = c.bifurcation;
      j["bifurcation_depth_mm"] =
          b.bifurcation_depth_m ? json(*b.bifurcation_depth_m * 1e3) : json(nullptr);
      j["bifurcation_verdict"] = dynamics::to_string(b.verdict);
      j["bifurcation_noise_floor_m"] = b.noise_floor_m;
      json islands = json::array();
      for (const auto& is : b.islands) {
        islands.push_back(
            {{"onset_depth_mm", is.onset_depth_m * 1e3}, {"end_depth_mm", is.end_depth_m * 1e3}});
      }
      j["chatter_islands"] = islands;
    } else {
      j["bifurcation_status"] = "skipped";
      j["bifurcation_skip_reason"] = c.bifurcation_status.message;
    }
  }
  json estimators = json::object();
  if (identified) {
    j["identification"] = estimation_json(c.estimation);
    j["offset_identified_relative_error"] = number_or_null(c.estimation.offset.relative_error);
    j["offset_identified_ambiguous"] = c.estimation.offset.search.ambiguous;
    for (const auto& v : c.estimation.variants) estimators[v.run.estimator] = variant_json(v);
    if (c.ramped) {
      json sim = json::object();
      for (const auto& s : c.estimation.simulated) {
        if (s.status.ok) {
          sim[s.chip_model] = {
              {"bifurcation_depth_mm", s.depth_m ? json(*s.depth_m * 1e3) : json(nullptr)},
              {"verdict", dynamics::to_string(s.verdict)},
              {"steps", s.steps},
              {"runtime_s", s.runtime_s}};
        } else {
          sim[s.chip_model] = {{"status", "failed"}, {"message", s.status.message}};
        }
      }
      j["simulated_identified"] = sim;
    }
  } else if (c.estimation.summary.message != "not run") {
    j["identification_status"] = "skipped";
    j["identification_skip_reason"] = c.estimation.summary.message;
  }
  j["estimators"] = estimators;
  return j;
}

json line_json(const cutting::FittedLine& l) {
  return {{"slope_N_m2", number_or_null(l.slope_N_per_m2)},
          {"intercept_N_m", number_or_null(l.intercept_N_per_m)},
          {"rms_residual_N", number_or_null(l.rms_residual_N)},
          {"r_squared", number_or_null(l.r_squared)}};
}

}  // namespace

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json results_json(const CampaignResults& r, const TruthComparison& truth) {
  json j;
  j["format"] = "chatterlab-results/1";
  j["campaign"] = r.campaign.name;
  j["generator"] = {{"name", "chatterlab"}, {"version", CHATTERLAB_VERSION}};
  json inputs = json::object();
  for (const auto& f : r.inputs) inputs[f.relative_path] = f.sha256;
  j["inputs_sha256"] = inputs;

  json tests = json::object();
  for (const auto& t : r.tests) {
    json e;
    e["kind"] = t.spec->kind;
    e["status"] = t.status.ok ? "ok" : "skipped";
    if (!t.status.ok) e["skip_reason"] = t.status.message;
    if (!t.warnings.empty()) e["warnings"] = t.warnings;
    e["runtime_s"] = t.runtime_s;
    if (t.status.ok && t.tap) e.update(tap_json(*t.tap));
    if (t.status.ok && t.dyno) e.update(dyno_json(*t.dyno));
    if (t.status.ok && t.cut) e.update(cut_json(*t.cut));
    tests[t.spec->id.empty() ? "." : t.spec->id] = e;
  }
  j["tests"] = tests;

  json groups = json::object();
  if (r.dyno_group) {
    const auto& g = *r.dyno_group;
    json d;
    d["tests"] = g.test_ids;
    if (g.summary.ok) {
      const auto& k = g.fit.coefficients;
      d["Ktc_N_m2"] = k.Ktc_N_per_m2;
      d["Kte_N_m"] = k.Kte_N_per_m;
      d["Krc_N_m2"] = k.Krc_N_per_m2;
      d["Kre_N_m"] = k.Kre_N_per_m;
      d["mean_force_model"] =
          g.fit.mean_force_model == cutting::SlotMeanForceModel::kSingleToothChip
              ? "single-tooth-chip"
              : "dissertation-eq-3.5";
      d["tangential_fit"] = line_json(g.fit.tangential);
      d["radial_fit"] = line_json(g.fit.radial);
      if (!g.summary.warnings.empty()) d["warnings"] = g.summary.warnings;
    } else {
      d["status"] = "skipped";
      d["skip_reason"] = g.summary.message;
    }
    groups["dyno-slot"] = d;
  }
  j["groups"] = groups;
  // The identification of one cut test (docs/identification.md, "Campaign values").
  if (const TestOutcome* src = identification_source(r)) {
    j["identified"] = identified_json(src->cut->estimation);
    j["identified_from"] = src->spec->id;
  } else {
    j["identified"] = json::object();
  }

  if (truth.present) {
    json rows = json::array();
    for (const auto& row : truth.rows) {
      rows.push_back({{"quantity", row.quantity},
                      {"source", row.source},
                      {"truth", row.truth},
                      {"estimate", row.estimate},
                      {"error_pct", row.error_pct}});
    }
    j["truth_comparison"] = rows;
  }
  j["runtime_s"] = r.runtime_s;
  return j;
}

}  // namespace chatterlab::app
