// results.json keys of a cut test (docs/formats.md, "results.json"): offset, measured
// bifurcation, identification passes, every estimator variant, and the campaign's
// `identified` block.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/core/checked_write.h"
#include "app/kinds/cut/cut_kind.h"
#include "app/report/results_json.h"

namespace chatterlab::app {

using nlohmann::json;

namespace {

json values_json(const estimate::ModalParameters& m,
                 const std::vector<estimate::ToothCoefficients>& k) {
  json j = json::object();
  for (const auto& [key, v] : keyed_values(m, k)) j[key] = number_or_null(v);
  return j;
}

// The sequence's identified values of one cut test (identification.identified).
json identified_json(const CutEstimation& e) {
  json j = values_json(e.modal, e.coefficients);
  // The scale-free combinations that deflection data determine on their own
  // (docs/identification.md, "Scale").
  for (const auto& [k, v] : scale_free_values(e)) j[k] = number_or_null(v);
  return j;
}

// The campaign's identified set (identified_set): every value, and its `<key>_ci95` pair when
// it has an interval.
json identified_set_json(const IdentifiedSet& s) {
  json j = json::object();
  for (const auto& v : s.values) {
    j[v.key] = number_or_null(v.value);
    if (!std::isnan(v.lo) || !std::isnan(v.hi)) {
      j[v.key + "_ci95"] = {number_or_null(v.lo), number_or_null(v.hi)};
    }
  }
  return j;
}

// Consistency of one filter's innovations (analysis/kalman/consistency.h).
json nis_json(const kalman::NisSummary& n) {
  return {{"updates", n.updates},
          {"dof", n.dof},
          {"mean", number_or_null(n.mean)},
          {"mean_band", {n.mean_band.lower, n.mean_band.upper}},
          {"mean_inside_band", n.mean_inside()},
          {"fraction_inside", number_or_null(n.fraction_inside)},
          {"confidence", n.confidence}};
}

json variant_json(const VariantOutcome& v) {
  const estimate::EkfResult& r = v.run;
  json j;
  if (!r.summary.ok()) {
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
  j["nis"] = nis_json(r.nis);
  if (r.nis_per_filter.size() > 1) {
    json per = json::array();
    for (const auto& n : r.nis_per_filter) per.push_back(nis_json(n));
    j["nis_per_filter"] = per;
  }
  j["filter"] = estimate::filter_name(r.id);
  j["known"] = v.known;
  j["start"] = v.start;
  if (v.observability_status.ok()) {
    j["observability_rank"] = v.observability.rank;
    j["observability_states"] = v.observability.states;
  } else {
    j["observability_message"] = v.observability_status.message;
  }
  const estimate::RepeatabilityResult& rep = v.repeat;
  if (!rep.keys.empty()) {
    json rj;
    rj["runs"] = rep.initial.rows();
    rj["status"] = rep.summary.ok() ? "ok" : "failed";
    if (!rep.summary.ok()) rj["message"] = rep.summary.message;
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

// The joint estimate (docs/identification.md, "Joint estimate"): every value with its 95 %
// interval as a `<key>_ci95` pair [lo, hi] (null ends along a near-singular direction), k held.
json joint_json(const estimate::JointIdentificationResult& r) {
  json j;
  j["method"] = "joint";
  if (!r.summary.ok()) {
    j["status"] = r.summary.ran() ? "failed" : "not run";
    j["message"] = r.summary.ran() ? r.summary.message
                                   : std::string("the identification sequence did not finish");
    return j;
  }
  j["status"] = "ok";
  json v = json::object();
  json weak = json::array();
  for (const auto& [key, iv] : keyed_intervals(r)) {
    v[key] = number_or_null(iv->value);
    v[key + "_ci95"] = {number_or_null(iv->lo), number_or_null(iv->hi)};
    if (!iv->identifiable) weak.push_back(key);
  }
  v["k_N_m"] = number_or_null(r.k_N_m);
  j["identified"] = v;
  j["k_held"] = "the sequence's k_N_m: deflections fix the values only up to a common scale";
  j["not_identifiable"] = weak;
  j["singular_directions"] = r.singular_directions;
  j["converged"] = r.converged;
  j["iterations_count"] = r.iterations;
  j["simulations_count"] = r.simulations;
  j["runtime_s"] = r.runtime_s;
  j["rms_error_m"] = number_or_null(r.rms_error_m);
  j["start_rms_error_m"] = number_or_null(r.start_rms_error_m);
  j["rms_relative_error"] = number_or_null(r.relative_error);
  j["residual_sd_m"] = number_or_null(r.residual_sd_m);
  j["residual_lag1_correlation_ratio"] = number_or_null(r.residual_correlation_lag1);
  j["correlation_lags_count"] = r.correlation_lags;
  j["variance_inflation_ratio"] = number_or_null(r.variance_inflation);
  j["jacobian_condition_ratio"] = number_or_null(r.condition);
  j["warnings"] = r.summary.warnings;
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
  j["method"] = "sequence";
  j["identified"] = identified_json(e);
  j["runtime_s"] = e.runtime_s;
  j["joint"] = joint_json(e.joint);
  return j;
}

// A cut test (EXPERIMENT_FORMAT.md: offset_angle_deg; bifurcation_depth_mm null when the run
// shows no bifurcation, absent when its depth does not vary). A step that did not succeed
// leaves its keys out and says why; bifurcation_depth_mm, which the format requires of every
// ramped cut, is then null beside bifurcation_status "skipped" (as in chatterlab simulate).
json cut_json(const CutOutcome& c) {
  json j;
  j["measured_rpm"] = number_or_null(c.tach.measured_rpm);
  j["tach_revolutions"] = c.tach.revolutions;
  j["air_revolutions"] = c.air_revolutions;
  const bool identified = c.estimation.summary.ok();
  if (c.offset_status.ok()) {
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
    if (c.bifurcation_status.ok()) {
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
      j["bifurcation_depth_mm"] = nullptr;  // not determined: bifurcation_status says why
      j["bifurcation_status"] = "skipped";
      j["bifurcation_skip_reason"] =
          c.bifurcation_status.ran() && !c.bifurcation_status.message.empty()
              ? c.bifurcation_status.message
              : std::string("the bifurcation detector did not run");
    }
  } else if (c.orbit_status.ok()) {
    // Constant depth: stable or chatter by the Poincare class (docs/lobes.md).
    j["orbit"] = dynamics::to_string(c.orbit.shape);
    j["orbit_period"] = c.orbit.period;
    j["chatter"] = c.orbit.shape != dynamics::OrbitShape::kFixedPoint;
    j["orbit_noise_floor_m"] = c.orbit_noise_floor_m;
  } else {
    j["orbit_status"] = "skipped";
    j["orbit_skip_reason"] = c.orbit_status.ran() && !c.orbit_status.message.empty()
                                 ? c.orbit_status.message
                                 : std::string("the orbit was not classified");
  }
  json estimators = json::object();
  if (identified) {
    j["identification"] = estimation_json(c.estimation);
    j["offset_identified_relative_error"] = number_or_null(c.estimation.offset.relative_error);
    j["offset_identified_ambiguous"] = c.estimation.offset.search.ambiguous;
    for (const auto& v : c.estimation.variants) estimators[v.run.estimator] = variant_json(v);
    const std::vector<FeedbackDifference> fd = feedback_differences(c.estimation);
    if (!fd.empty()) {
      json d = json::object();
      for (const auto& f : fd) {
        d[f.key.substr(0, f.key.find('_')) + "_difference_pct"] = number_or_null(f.difference_pct);
      }
      j["chip_feedback"] = d;
    }
    if (c.ramped) {
      json sim = json::object();
      for (const auto& s : c.estimation.simulated) {
        if (s.status.ok()) {
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
  } else if (c.estimation.summary.ran()) {
    j["identification_status"] = "skipped";
    j["identification_skip_reason"] = c.estimation.summary.message;
  }
  j["estimators"] = estimators;
  return j;
}

}  // namespace

json CutKind::results(const TestOutcome& t) const {
  json j = cut_json(t.result_of<CutOutcome>());
  if (t.result_of<CutOutcome>().estimation.summary.ok())
    j["identified_csv"] = identified_csv_path(t.spec->id);
  return j;
}

std::string identified_csv_path(const std::string& test_id) {
  return (test_id.empty() ? std::string() : test_id + "/") + "identified.csv";
}

std::string unit_of_key(const std::string& key) {
  // Longest suffix first: _N_m2 before _N_m, _kg_s before _s.
  static const std::pair<const char*, const char*> kUnits[] = {
      {"_N_m2", "N/m^2"}, {"_N_m", "N/m"}, {"_kg_s", "kg/s"}, {"_kg", "kg"},
      {"_per_m", "1/m"},  {"_hz", "Hz"},   {"_deg", "deg"},   {"_s", "s"}};
  for (const auto& [suffix, unit] : kUnits) {
    const std::string sf(suffix);
    if (key.size() > sf.size() && key.compare(key.size() - sf.size(), sf.size(), sf) == 0) {
      return unit;
    }
  }
  return "-";
}

// The identified values of one cut test as a table: quantity,value,unit (the keys of
// results.json `identified`, in its order; an empty value for a non-finite one).
void CutKind::write_files(const TestOutcome& t, const std::filesystem::path& report_dir) const {
  const CutOutcome& c = t.result_of<CutOutcome>();
  if (!c.estimation.summary.ok()) return;
  const std::filesystem::path file = report_dir / identified_csv_path(t.spec->id);
  std::filesystem::create_directories(file.parent_path());
  std::ofstream out = open_for_writing(file);
  out << "# chatterlab " << CHATTERLAB_VERSION << ": values identified from cut test "
      << (t.spec->id.empty() ? std::string(".") : t.spec->id)
      << " (the joint estimate when it succeeded, results.json "
         "tests.<id>.identification.joint.identified, else the sequence's, "
         "tests.<id>.identification.identified; the campaign's `identified` when identified_from "
         "names this test)\n";
  const IdentifiedSet set = identified_set(c.estimation);
  out << "# method: " << set.method
      << (set.method == "joint" ? " (95 % intervals in ci95_lo, ci95_hi)" : " (no intervals)")
      << "\n";
  out << "quantity,value,unit,ci95_lo,ci95_hi\n";
  char buf[40];
  auto number = [&](double v) {
    if (!std::isfinite(v)) return std::string();
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  for (const auto& v : set.values) {
    out << v.key << ',' << number(v.value) << ',' << unit_of_key(v.key) << ',' << number(v.lo)
        << ',' << number(v.hi) << '\n';
  }
  close_checked(out, file);
}

// The identification of one cut test (docs/identification.md, "Campaign values").
void CutKind::campaign_results(const CampaignResults& r, json& root) const {
  if (const TestOutcome* src = identification_source(r)) {
    const IdentifiedSet set = identified_set(src->result_of<CutOutcome>().estimation);
    root["identified"] = identified_set_json(set);
    root["identified_method"] = set.method;
    root["identified_from"] = src->spec->id;
    root["identified_csv"] = identified_csv_path(src->spec->id);
  } else {
    root["identified"] = json::object();
  }
}

}  // namespace chatterlab::app
