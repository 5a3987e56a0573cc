#include "app/report/results_json.h"

#include <cmath>

#include "analysis/common/library_versions.h"
#include "app/git_commit.h"

namespace chatterlab::app {

using nlohmann::json;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json number_array(const Eigen::Ref<const Eigen::VectorXd>& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

const char* status_word(const StepSummary& status, Failure failure) {
  if (status.ok()) return "ok";
  return failure == Failure::kInternal ? "error" : "skipped";
}

json settings_json(const CampaignResults& r) {
  json s = json::object();
  for (const auto& entry : r.kinds->in_order()) {
    if (entry.kind) {
      const json k = entry.kind->settings(r.campaign);
      if (!k.empty()) s[entry.kind->name()] = k;
    } else {
      const json g = entry.group->settings(r.campaign);
      if (!g.empty()) s["group:" + entry.group->name()] = g;
    }
  }
  s["pipeline"] = {{"jobs", r.options.jobs}};
  return s;
}

json provenance_json(const CampaignResults& r) {
  const LibraryVersions lib = library_versions();
  json levels = json::array();
  for (const auto& level : r.levels) levels.push_back(level);
  return {{"version", CHATTERLAB_VERSION},
          {"git_commit", CHATTERLAB_GIT_COMMIT},
          {"libraries", {{"eigen", lib.eigen}, {"ceres", lib.ceres}, {"fftw", lib.fftw}}},
          {"run_order", levels}};
}

json figure_files_json(const FigureSet& figures, const std::string& owner) {
  json files = json::object();
  if (const auto it = figures.stems.find(owner); it != figures.stems.end()) {
    for (const auto& [key, stem] : it->second) {
      files[key]["svg"] = stem + ".svg";
      files[key]["png"] = stem + ".png";
    }
  }
  if (const auto it = figures.data.find(owner); it != figures.data.end()) {
    for (const auto& [key, csv] : it->second) files[key]["csv"] = csv;
  }
  return files;
}

json results_json(const CampaignResults& r, const TruthComparison& truth,
                  const FigureSet& figures) {
  json j;
  j["format"] = "chatterlab-results/1";
  j["campaign"] = r.campaign.name;
  j["generator"] = {{"name", "chatterlab"}, {"version", CHATTERLAB_VERSION}};
  json inputs = json::object();
  for (const auto& f : r.inputs) inputs[f.relative_path] = f.sha256;
  j["inputs_sha256"] = inputs;
  j["provenance"] = provenance_json(r);
  j["settings"] = settings_json(r);

  json tests = json::object();
  for (const auto& t : r.tests) {
    json e;
    e["kind"] = t.spec->kind;
    e["status"] = status_word(t.status, t.failure);
    if (!t.status.ok()) e["skip_reason"] = t.status.message;
    if (!t.warnings.empty()) e["warnings"] = t.warnings;
    e["runtime_s"] = t.runtime_s;
    if (t.status.ok()) {
      if (const TestKind* kind = r.kinds->find(t.spec->kind)) e.update(kind->results(t));
      e["figures"] = figure_files_json(figures, t.spec->id);
    }
    tests[t.spec->id.empty() ? "." : t.spec->id] = e;
  }
  j["tests"] = tests;

  json groups = json::object();
  for (const auto& g : r.groups) {
    const GroupProduct* p = r.kinds->find_group(g.name);
    if (p == nullptr) continue;
    json e = p->results(g);
    if (g.status.ok()) e["figures"] = figure_files_json(figures, "group:" + g.name);
    groups[g.name] = e;
  }
  j["groups"] = groups;
  for (const auto& k : r.kinds->kinds()) k->campaign_results(r, j);

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
  j["internal_errors"] = r.internal_errors();
  j["runtime_s"] = r.runtime_s;
  return j;
}

}  // namespace chatterlab::app
