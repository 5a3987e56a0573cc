#include "app/nightly/nightly.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/common/stopwatch.h"
#include "analysis/common/summary.h"
#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "app/cli/progress.h"
#include "app/core/archive.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/hashing.h"
#include "app/core/input_boundary.h"
#include "app/git_commit.h"
#include "app/nightly/cache_keys.h"
#include "app/nightly/compute.h"
#include "app/nightly/site_db.h"
#include "app/nightly/test_cache.h"
#include "app/nightly/trends.h"
#include "app/report/document.h"
#include "app/report/report.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Whether `inner` is `outer` or lies below it (both made absolute and canonical as far as they
// exist).
bool inside(const fs::path& inner, const fs::path& outer) {
  std::error_code ec;
  const auto i = fs::weakly_canonical(fs::absolute(inner), ec);
  const auto o = fs::weakly_canonical(fs::absolute(outer), ec);
  const auto r = i.lexically_relative(o);
  return !r.empty() && *r.begin() != "..";
}

// A site folder is ours when it is absent, empty or holds a site database or nightly.json.
void check_site(const fs::path& site, const fs::path& root) {
  if (inside(root, site)) {
    throw InputError("--out " + site.string() +
                     ": is the archive root or holds it; choose a site folder outside the root");
  }
  std::error_code ec;
  if (fs::is_symlink(site, ec)) {
    throw InputError("--out " + site.string() + ": is a symbolic link; give the folder itself");
  }
  if (!fs::exists(site, ec)) return;
  if (!fs::is_directory(site, ec)) {
    throw InputError("--out " + site.string() + ": is not a folder");
  }
  if (fs::is_empty(site, ec) || fs::exists(site / "history.sqlite", ec) ||
      fs::exists(site / "nightly.json", ec) || fs::exists(site / ".nightly.lock", ec)) {
    return;
  }
  throw InputError("--out " + site.string() +
                   ": is not a chatterlab nightly site (no history.sqlite or nightly.json) and not "
                   "empty; choose a new or empty folder");
}

// The campaign's folder name in the site: results.json's campaign name, made unique by its
// path when two campaigns share a name, and by a short hash of the path when that is not enough.
std::map<std::string, std::string> site_names(const std::vector<ArchiveCampaign>& found,
                                              const std::vector<std::string>& names) {
  std::map<std::string, int> count;
  for (const auto& n : names) ++count[n];
  std::map<std::string, std::string> out;
  for (std::size_t i = 0; i < found.size(); ++i) {
    std::string n = names[i];
    if (count[n] > 1) {
      std::string p = found[i].path;
      for (char& ch : p) {
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '.' && ch != '_' && ch != '-') {
          ch = '-';
        }
      }
      n += "@" + p;
    }
    // A plain child of campaigns/: never "." or "..", never hidden (the temporary folders and
    // locks beside the report folders are).
    if (n.empty() || n[0] == '.') n = "campaign-" + n;
    out[found[i].path] = n;
  }
  // Two paths can sanitize alike ("lab/a" and "lab-a"): such names take a short hash of their
  // path, so that no two campaigns share a folder or a row of the history.
  std::map<std::string, int> taken;
  for (const auto& [path, n] : out) ++taken[n];
  for (auto& [path, n] : out) {
    if (taken[n] > 1) n += "-" + sha256_text(path).substr(0, 8);
  }
  return out;
}

std::string utc_now() { return utc_timestamp_iso(); }

// The program in the cache keys: version, commit and the SHA-256 of the executable itself, so
// that two builds of one commit with local changes ("<commit>-modified") never share a key.
std::string program_identity() {
  std::string id = std::string(CHATTERLAB_VERSION) + " " + CHATTERLAB_GIT_COMMIT;
  try {
    id += " " + sha256_file("/proc/self/exe");
  } catch (const InputError&) {
    id += " unhashed";
  }
  return id;
}

// A campaign's share of the exit status: one not read, of which no test was analysed, or whose
// report.pdf could not be written (as `report` exits 1 then) is bad input the lab must see; an
// internal error is reported as such.
int campaign_exit_code(const std::string& status) {
  if (status == "unreadable" || status == "nothing-analysed" || status == "pdf-not-written") {
    return kExitInputError;
  }
  if (status == "internal-error") return kExitInternalError;
  return kExitOk;
}

// What the site shows of one campaign, from its results.json.
struct CampaignState {
  std::string name;  // folder name in the site
  std::string path;  // relative to the root
  std::string status = "ok";
  std::string message;
  std::string last_change_utc;
  std::vector<std::string> recomputed, cached, changed;
  json flags = json::array();
  json results;  // null when the campaign has no report
  int exit_code = kExitOk;
  std::string series;  // the trend pages' series: its tool's, else its own name
};

// The series of a campaign on the trend pages: those sharing a tool (teeth and radius) are one,
// named after it; the tool comes from results.json when it holds one, else from campaign.yaml.
// A campaign without a tool is a series of its own, named by the campaign.
std::string campaign_series(const json& results, const fs::path& folder, const std::string& name) {
  if (results.is_object()) {
    if (const auto t = results.find("tool"); t != results.end() && t->is_object()) {
      const auto teeth = t->find("teeth");
      const auto r = t->find("radius_mm");
      if (teeth != t->end() && teeth->is_number_integer() && r != t->end() && r->is_number()) {
        return tool_series_name(teeth->get<int>(), r->get<double>());
      }
    }
  }
  try {
    const CampaignSpec c = load_campaign(folder);
    if (c.tool && c.tool->teeth > 0) return tool_series_name(c.tool->teeth, c.tool->radius_m * 1e3);
  } catch (const std::exception&) {  // no readable campaign.yaml: no tool
  }
  return name;
}

json headline_values(const json& results) {
  json rows = json::array();
  if (!results.is_object()) return rows;
  const auto it = results.find("identified");
  if (it == results.end() || !it->is_object()) return rows;
  for (auto v = it->begin(); v != it->end(); ++v) {
    if (!v->is_number() || v.key().find("_over_k") != std::string::npos) continue;
    json row = {{"key", v.key()}, {"value", v->get<double>()}};
    if (const auto ci = it->find(v.key() + "_ci95");
        ci != it->end() && ci->is_array() && ci->size() == 2) {
      row["ci95"] = *ci;
    }
    rows.push_back(row);
  }
  return rows;
}

// Each cut's estimator finals (results.json tests.<id>.estimators.<variant>.estimates), keyed
// "<test id>/<variant>/<estimate key>" for the trend table; a failed variant has none.
json estimator_finals(const json& results) {
  json rows = json::array();
  if (!results.is_object()) return rows;
  const auto tests = results.find("tests");
  if (tests == results.end() || !tests->is_object()) return rows;
  for (auto t = tests->begin(); t != tests->end(); ++t) {
    if (!t->is_object()) continue;
    const auto est = t->find("estimators");
    if (est == t->end() || !est->is_object()) continue;
    for (auto v = est->begin(); v != est->end(); ++v) {
      if (!v->is_object()) continue;
      const auto e = v->find("estimates");
      if (e == v->end() || !e->is_object()) continue;
      for (auto k = e->begin(); k != e->end(); ++k) {
        if (!k->is_number()) continue;
        rows.push_back(
            {{"key", t.key() + "/" + v.key() + "/" + k.key()}, {"value", k->get<double>()}});
      }
    }
  }
  return rows;
}

json skipped_tests(const json& results) {
  json rows = json::array();
  if (!results.is_object() || !results.contains("tests")) return rows;
  for (auto t = results["tests"].begin(); t != results["tests"].end(); ++t) {
    const std::string status = t->value("status", "");
    if (status == "ok") continue;
    rows.push_back({{"id", t.key()}, {"status", status}, {"reason", t->value("message", "")}});
  }
  return rows;
}

}  // namespace

std::vector<ArchiveCampaign> find_campaigns(const fs::path& root, const fs::path& skip) {
  std::vector<ArchiveCampaign> out;
  std::error_code ec;
  if (fs::is_regular_file(root / "campaign.yaml", ec)) return {{".", root}};
  // A scan that stops half-way (a folder removed meanwhile, an I/O error on a share) would
  // look like campaigns that left the archive: it is an error.
  const auto scan_failed = [&root](const std::error_code& e) {
    return InputError(root.string() +
                      ": the archive root cannot be read to the end: " + e.message());
  };
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec);
  if (ec) throw scan_failed(ec);
  const auto next = [&] {
    it.increment(ec);
    if (ec) throw scan_failed(ec);
  };
  for (; it != fs::recursive_directory_iterator(); next()) {
    std::error_code e2;
    if (it->is_symlink(e2) || !it->is_directory(e2)) {
      if (it->is_symlink(e2)) it.disable_recursion_pending();
      continue;
    }
    if (!skip.empty() && inside(it->path(), skip)) {
      it.disable_recursion_pending();
      continue;
    }
    if (fs::is_regular_file(it->path() / "campaign.yaml", e2)) {
      out.push_back({fs::relative(it->path(), root).generic_string(), it->path()});
      it.disable_recursion_pending();  // campaigns do not nest
    }
  }
  std::sort(out.begin(), out.end(),
            [](const ArchiveCampaign& a, const ArchiveCampaign& b) { return a.path < b.path; });
  return out;
}

namespace {

// One campaign of a run as planned under the site's lock: its keys, what changed since the
// site's last run and whether its report folder can stay as it is. A --slurm run writes the
// plans into plan.json for its reduce job (from_json reads them back).
struct CampaignPlan {
  std::string path;                                  // relative to the root
  std::string name;                                  // folder name in the site
  fs::path folder;                                   // the campaign folder
  std::map<std::string, std::string> tests, groups;  // cache keys (app/nightly/cache_keys.h)
  std::string campaign_key;
  std::vector<std::string> changed, spec_errors;
  bool reusable = false;
  std::string prev_change, prev_status, prev_message;

  json to_json() const {
    return {{"path", path},
            {"name", name},
            {"folder", folder.string()},
            {"tests", tests},
            {"groups", groups},
            {"campaign_key", campaign_key},
            {"changed", changed},
            {"spec_errors", spec_errors},
            {"reusable", reusable},
            {"prev_change", prev_change},
            {"prev_status", prev_status},
            {"prev_message", prev_message}};
  }
  static CampaignPlan from_json(const json& j) {
    CampaignPlan p;
    p.path = j.at("path").get<std::string>();
    p.name = j.at("name").get<std::string>();
    p.folder = j.at("folder").get<std::string>();
    p.tests = j.at("tests").get<std::map<std::string, std::string>>();
    p.groups = j.at("groups").get<std::map<std::string, std::string>>();
    p.campaign_key = j.at("campaign_key").get<std::string>();
    p.changed = j.at("changed").get<std::vector<std::string>>();
    p.spec_errors = j.at("spec_errors").get<std::vector<std::string>>();
    p.reusable = j.at("reusable").get<bool>();
    p.prev_change = j.at("prev_change").get<std::string>();
    p.prev_status = j.at("prev_status").get<std::string>();
    p.prev_message = j.at("prev_message").get<std::string>();
    return p;
  }
};

std::vector<CampaignPlan> plan_campaigns(const fs::path& site, SiteDb& db,
                                         const std::vector<ArchiveCampaign>& found,
                                         const std::string& program, bool pdf,
                                         std::int64_t run_id) {
  std::error_code ec;
  std::vector<CampaignSpec> specs;
  std::vector<std::string> names;
  for (const auto& a : found) {
    specs.push_back(load_campaign(a.folder));
    names.push_back(results_campaign_name(specs.back()));
  }
  const std::map<std::string, std::string> site_name = site_names(found, names);
  std::vector<CampaignPlan> plans;
  for (std::size_t i = 0; i < found.size(); ++i) {
    const ArchiveCampaign& a = found[i];
    CampaignPlan p;
    p.path = a.path;
    p.name = site_name.at(a.path);
    p.folder = a.folder;
    p.spec_errors = specs[i].errors;
    // Keys that cannot be made (a broken invariant) make the campaign's key new in every run.
    std::string unkeyed;
    try {
      const CampaignKeys keys = campaign_keys(specs[i], program);
      p.tests = keys.tests;
      p.groups = keys.groups;
    } catch (const std::exception& e) {
      unkeyed = "unkeyed in run " + std::to_string(run_id) + ": " + e.what() + "\n";
    }
    // The program and campaign.yaml as well, for a campaign without tests.
    std::string key_text = "pdf=" + std::to_string(pdf) + "\nprogram " + program + "\n";
    try {
      // Read only inside the boundary (app/core/input_boundary.h): a campaign.yaml linked out of
      // its folder is refused by the loader and never read, for its hash neither.
      const fs::path yaml = a.folder / "campaign.yaml";
      key_text += "campaign.yaml " +
                  (regular_file_inside(a.folder, yaml) ? sha256_file(yaml)
                                                       : std::string("outside the campaign")) +
                  "\n";
    } catch (const InputError&) {
      key_text += "campaign.yaml unreadable\n";
    }
    key_text += unkeyed;
    for (const auto& [t, k] : p.tests) key_text += t + " " + k + "\n";
    for (const auto& [g, k] : p.groups) key_text += g + " " + k + "\n";
    p.campaign_key = sha256_text(key_text);

    // The previous run's state of this campaign.
    std::map<std::string, std::string> stored;
    {
      SiteDb::Statement s(db, "SELECT test, key_sha256 FROM test_cache WHERE campaign = ?");
      s.bind(1, p.name);
      while (s.step()) stored[s.text(0)] = s.text(1);
    }
    std::string prev_key, prev_results_sha;
    {
      SiteDb::Statement s(db,
                          "SELECT campaign_key, results_sha256, last_change_utc, status, message "
                          "FROM campaign_runs WHERE name = ? ORDER BY run_id DESC LIMIT 1");
      s.bind(1, p.name);
      if (s.step()) {
        prev_key = s.text(0);
        prev_results_sha = s.text(1);
        p.prev_change = s.text(2);
        p.prev_status = s.text(3);
        p.prev_message = s.text(4);
      }
    }
    for (const auto& [t, k] : p.tests) {
      const auto it = stored.find(t);
      if (it == stored.end() || it->second != k) p.changed.push_back(t);
    }
    // Only a campaign whose last report was complete is left as it is: a missing report.pdf or
    // an internal error is tried again in every run.
    const fs::path results_file = site / "campaigns" / p.name / "results.json";
    p.reusable = (p.prev_status == "ok" || p.prev_status == "nothing-analysed") &&
                 !prev_key.empty() && prev_key == p.campaign_key &&
                 fs::is_regular_file(results_file, ec) &&
                 sha256_file(results_file) == prev_results_sha;
    plans.push_back(std::move(p));
  }
  return plans;
}

// Every node of a campaign with its cache key: its tests and its groups ("group:<name>").
std::map<std::string, std::string> node_keys(const CampaignPlan& p) {
  std::map<std::string, std::string> k = p.tests;
  k.insert(p.groups.begin(), p.groups.end());
  return k;
}

// The kinds' results the site holds for a campaign (app/nightly/test_cache.h), by node.
std::map<std::string, SiteResultCache::Stored> stored_results(SiteDb& db,
                                                              const std::string& campaign) {
  std::map<std::string, SiteResultCache::Stored> out;
  SiteDb::Statement s(db, "SELECT test, key_sha256, result FROM test_cache WHERE campaign = ?");
  s.bind(1, campaign);
  while (s.step()) {
    if (s.is_null(2)) continue;
    out[s.text(0)] = {s.text(1), s.blob(2)};
  }
  return out;
}

// The campaign's report of the last run, for the regression flags (null when there is none).
json previous_results(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_regular_file(folder / "results.json", ec)) return nullptr;
  try {
    return read_json_file(folder / "results.json");
  } catch (const InputError&) {
    return nullptr;
  }
}

// The campaign's state after this run, recorded in the history in one transaction: left as it
// was (`outcome` null), or recomputed (`outcome` says how; its report folder is in place when
// outcome->written). Folders to remove once the index is in place go to `remove_after_index`.
CampaignState finish_campaign(const fs::path& site, SiteDb& db, std::int64_t run_id,
                              const CampaignPlan& p, const ComputeOutcome* outcome,
                              const SiteResultCache* cache, const json& previous,
                              const CompareOptions& tolerances,
                              std::vector<fs::path>& remove_after_index) {
  std::error_code ec;
  const fs::path folder = site / "campaigns" / p.name;
  const fs::path results_file = folder / "results.json";
  CampaignState st;
  st.path = p.path;
  st.name = p.name;
  st.changed = p.changed;
  bool failed = false;          // no report of this run: no keys kept, never reused
  bool recomputed_now = false;  // a new report folder is in place, its results recorded
  if (outcome == nullptr) {
    for (const auto& [t, k] : p.tests) st.cached.push_back(t);
    st.last_change_utc = p.prev_change;
    st.results = previous;
    st.status = p.prev_status;
    st.message = p.prev_message;
  } else {
    st.last_change_utc = utc_now();
    // The campaign's own errors first (a campaign.yaml that does not parse), then the run's.
    for (const auto& e : p.spec_errors) st.message += e + "\n";
    st.message += outcome->errors;
    while (!st.message.empty() && st.message.back() == '\n') st.message.pop_back();
    if (outcome->internal) {
      // A bug, a figure or template error, a lock or commit that failed: the previous report
      // folder stays as it was; nothing was computed, and the campaign is tried again in the
      // next run.
      st.status = "internal-error";
      failed = true;
    } else if (!outcome->written) {
      st.status = "unreadable";
      failed = true;
      // No report shows numbers of a campaign that did not run (removed once the index is in
      // place).
      remove_after_index.push_back(folder);
    } else {
      // The tests restored from the per-test cache were not computed (their keys did not
      // change); the others were.
      const std::vector<std::string> restored =
          cache ? cache->restored() : std::vector<std::string>{};
      for (const auto& [t, k] : p.tests) {
        const bool was_restored = std::binary_search(restored.begin(), restored.end(), t);
        (was_restored ? st.cached : st.recomputed).push_back(t);
      }
      recomputed_now = true;
      const int rc = outcome->exit_code;
      st.status = rc == kExitOk                ? "ok"
                  : rc == kExitInternalError   ? "internal-error"
                  : rc == kExitNothingAnalysed ? "nothing-analysed"
                                               : "pdf-not-written";
      st.results = read_json_file(results_file);
      if (previous.is_object()) {
        const Comparison c = compare_results(previous, st.results, tolerances);
        for (const auto& ch : c.changes) {
          if (ch.flag) st.flags.push_back(ch.key);
        }
      }
    }
  }
  st.exit_code = campaign_exit_code(st.status);
  st.series = campaign_series(st.results, p.folder, st.name);
  if (!st.flags.empty() && st.exit_code == kExitOk) st.exit_code = kExitFlagged;

  // The kinds' results to keep: computed now or restored (the cache says which). A campaign
  // left as it was keeps its rows as they are (its keys are the stored ones, since its campaign
  // key is made of them): only the run they were last confirmed in moves.
  SiteDb::Transaction t(db);
  if (outcome == nullptr) {
    SiteDb::Statement touch(db, "UPDATE test_cache SET run_id = ? WHERE campaign = ?");
    touch.bind(1, run_id).bind(2, st.name);
    touch.step();
  } else {
    SiteDb::Statement del(db, "DELETE FROM test_cache WHERE campaign = ?");
    del.bind(1, st.name);
    del.step();
  }
  if (outcome != nullptr && !failed) {
    SiteDb::Statement put(db,
                          "INSERT INTO test_cache (campaign, test, key_sha256, payload, run_id, "
                          "result) VALUES (?, ?, ?, ?, ?, ?)");
    for (const auto& [node, key] : node_keys(p)) {
      json entry;
      const json& results = st.results;  // read only: no "tests": null inserted
      if (const auto tests = results.is_object() ? results.find("tests") : results.end();
          tests != results.end() && tests->is_object()) {
        if (const auto it = tests->find(node); it != tests->end()) entry = *it;
      }
      put.reset();
      put.bind(1, st.name).bind(2, node).bind(3, key).bind_blob(4, entry.dump());
      put.bind(5, run_id);
      const std::optional<std::string> result =
          cache != nullptr ? cache->compressed_to_store(node) : std::nullopt;
      if (result) {
        put.bind_blob(6, *result);
      } else {
        put.bind_null(6);
      }
      put.step();
    }
  }
  SiteDb::Statement row(db,
                        "INSERT INTO campaign_runs (run_id, name, path, status, message, "
                        "last_change_utc, recomputed, cached, flags, campaign_key, "
                        "results_sha256, results) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  row.bind(1, run_id).bind(2, st.name).bind(3, st.path).bind(4, st.status);
  row.bind(5, st.message).bind(6, st.last_change_utc).bind(7, json(st.recomputed).dump());
  row.bind(8, json(st.cached).dump()).bind(9, st.flags.dump());
  row.bind(10, failed ? std::string() : p.campaign_key);
  const bool has_results = fs::is_regular_file(results_file, ec);
  row.bind(11, has_results ? sha256_file(results_file) : std::string());
  if (recomputed_now && st.results.is_object()) {
    row.bind_blob(12, st.results.dump());
  } else {
    row.bind_null(12);
  }
  row.step();
  SiteDb::Statement val(db,
                        "INSERT INTO trend_values (run_id, campaign, key, value, lo, hi) VALUES "
                        "(?, ?, ?, ?, ?, ?)");
  json values = headline_values(st.results);
  for (const auto& v : estimator_finals(st.results)) values.push_back(v);
  for (const auto& v : values) {
    val.reset();
    val.bind(1, run_id).bind(2, st.name).bind(3, v["key"].get<std::string>());
    val.bind(4, v["value"].get<double>());
    // An interval end that is not a number (null: not finite in results.json) stays NULL.
    const json ci = v.value("ci95", json());
    for (int end = 0; end < 2; ++end) {
      if (ci.is_array() && ci.size() == 2 && ci[end].is_number()) {
        val.bind(5 + end, ci[end].get<double>());
      } else {
        val.bind_null(5 + end);
      }
    }
    val.step();
  }
  t.commit();
  return st;
}

// The run's exit status with one more campaign: an internal error wins, else the first
// campaign that is not ok sets it.
int with_campaign(int exit_code, const CampaignState& st) {
  if (st.exit_code == kExitInternalError || exit_code == kExitOk) {
    return std::max(exit_code, st.exit_code);
  }
  return exit_code;
}

void log_campaign(std::ostream& log, std::ostream& err, std::size_t i, std::size_t n,
                  const CampaignState& st, double seconds) {
  log << "[" << (i + 1) << "/" << n << "] " << st.path << " (" << st.name << "): " << st.status
      << ", " << st.recomputed.size() << " recomputed, " << st.cached.size() << " cached";
  if (!st.flags.empty()) log << ", " << st.flags.size() << " flagged";
  log << ", " << format_duration(seconds) << std::endl;
  if (!st.message.empty() && st.status != "ok") {
    err << "nightly: " << st.path << ": " << st.message << "\n";
  }
}

void install_staged_report(const fs::path& staged, const fs::path& dest);

// The end of a run: the index page, the trend and estimator pages and nightly.json, the report
// folders that leave the site, the run marked done. Returns the exit status (`exit_code`, raised
// when the index's PDF was not written).
int write_site_index(const std::string& root_label, const fs::path& site, SiteDb& db,
                     std::int64_t run_id, const std::string& started, double runtime, bool pdf,
                     const std::vector<CampaignState>& states,
                     std::vector<fs::path> remove_after_index, int exit_code,
                     const CompareOptions& tolerances, int jobs, std::ostream& log,
                     std::ostream& err) {
  std::error_code ec;
  // Report folders of campaigns no longer in the archive leave the site (their history stays),
  // once the index that no longer links them is in place.
  std::set<std::string> current;
  for (const auto& s : states) current.insert(s.name);
  for (const auto& e : fs::directory_iterator(site / "campaigns", ec)) {
    const std::string n = e.path().filename().string();
    if (n.empty() || n[0] == '.' || current.count(n)) continue;
    remove_after_index.push_back(e.path());
  }

  // nightly.json and the index page, written into a staging folder in the site and renamed
  // into place one by one, nightly.json last: a nightly.json of this run marks it complete.
  json campaigns = json::object();
  json rows = json::array();
  for (const auto& s : states) {
    json c = {{"path", s.path},
              {"status", s.status},
              {"recomputed", s.recomputed},
              {"cached", s.cached},
              {"changed", s.changed},
              {"flags", s.flags},
              {"last_change_utc", s.last_change_utc}};
    if (s.results.is_object()) c["results"] = "campaigns/" + s.name + "/results.json";
    if (!s.message.empty()) c["message"] = s.message;
    campaigns[s.name] = c;
    const json skipped = skipped_tests(s.results);
    json values = json::array();
    for (const auto& v : headline_values(s.results)) {
      std::string text = v["key"].get<std::string>() + " = " + fmt_sig(v["value"].get<double>(), 4);
      if (v.contains("ci95") && v["ci95"].is_array() && v["ci95"].size() == 2 &&
          v["ci95"][0].is_number() && v["ci95"][1].is_number()) {
        text += " [" + fmt_sig(v["ci95"][0].get<double>(), 4) + ", " +
                fmt_sig(v["ci95"][1].get<double>(), 4) + "]";
      }
      values.push_back(text);
    }
    const int tests = s.results.is_object() && s.results.contains("tests")
                          ? static_cast<int>(s.results["tests"].size())
                          : 0;
    rows.push_back({{"name", s.name},
                    {"path", s.path},
                    {"status", s.status},
                    {"ok", s.status == "ok"},
                    {"has_report", s.results.is_object()},
                    {"message", s.message},
                    {"last_change", s.last_change_utc},
                    {"tests", tests},
                    {"tests_ok", tests - static_cast<int>(skipped.size())},
                    {"recomputed", s.recomputed.size()},
                    {"cached", s.cached.size()},
                    {"skipped", skipped},
                    {"values", values},
                    {"flags", s.flags},
                    {"flag_count", s.flags.size()}});
  }
  const json nightly = {{"format", "chatterlab-nightly/1"},
                        {"runtime_s", runtime},
                        {"version", CHATTERLAB_VERSION},
                        {"started_utc", started},
                        {"campaigns", campaigns}};
  const fs::path stage = site / ".index-tmp";
  fs::remove_all(stage, ec);
  fs::create_directories(stage);
  write_file_checked(stage / "nightly.json", nightly.dump(2) + "\n");
  json ctx = {{"generated_utc", utc_timestamp()},
              {"generated_iso", utc_timestamp_iso()},
              {"version", CHATTERLAB_VERSION},
              {"root", root_label},
              {"campaign_count", states.size()},
              {"runtime", format_duration(runtime)},
              {"campaigns", rows}};
  std::ostringstream doc_log;
  DocumentOptions dopt;
  dopt.pdf = pdf;
  const bool pdf_written = write_documents("nightly.html", ctx, stage, dopt, "nightly", doc_log);
  if (pdf && !pdf_written) {
    err << doc_log.str();
    exit_code = std::max(exit_code, static_cast<int>(kExitInputError));
  }
  // The trend and estimator pages, their figures put in place before the pages that show them.
  std::vector<TrendCampaign> trend_campaigns;
  for (const auto& s : states) trend_campaigns.push_back({s.name, s.series, s.results});
  const TrendPages trends = write_trend_pages(stage, db, run_id, trend_campaigns, tolerances,
                                              {{"root", root_label},
                                               {"version", CHATTERLAB_VERSION},
                                               {"generated_utc", ctx["generated_utc"]},
                                               {"generated_iso", ctx["generated_iso"]}},
                                              jobs);
  for (const auto& e : trends.errors) err << "nightly: trends: " << e << "\n";
  install_staged_report(stage / "figures", site / "figures");
  // No report.pdf of an earlier run beside this run's index page.
  if (!pdf_written) fs::remove(site / "report.pdf", ec);
  for (const char* f : {"report.css", "index.html", "trends.html", "estimators.html", "report.pdf",
                        "nightly.json"}) {
    if (f == std::string("report.pdf") && !pdf_written) continue;
    if (fs::exists(stage / f, ec)) fs::rename(stage / f, site / f);
  }
  fs::remove_all(stage, ec);
  for (const auto& f : remove_after_index) fs::remove_all(f, ec);
  {
    SiteDb::Transaction t(db);
    SiteDb::Statement s(db,
                        "UPDATE runs SET finished_utc = ?, runtime_s = ?, status = 'done' WHERE "
                        "id = ?");
    s.bind(1, utc_now()).bind(2, runtime).bind(3, run_id);
    s.step();
    t.commit();
  }
  log << "nightly: " << states.size() << " " << (states.size() == 1 ? "campaign" : "campaigns")
      << " in " << format_duration(runtime) << "; wrote " << (site / "index.html").string()
      << ", nightly.json\n";
  return exit_code;
}

std::string root_label(const fs::path& root) {
  return root.filename().empty() ? root.parent_path().filename().string()
                                 : root.filename().string();
}

// Records a run that an exception ended as failed (the exception goes on to the caller).
void mark_failed(SiteDb& db, std::int64_t run_id) {
  try {
    SiteDb::Transaction t(db);
    SiteDb::Statement s(db, "UPDATE runs SET finished_utc = ?, status = 'failed' WHERE id = ?");
    s.bind(1, utc_now()).bind(2, run_id);
    s.step();
    t.commit();
  } catch (const std::exception&) {  // the database itself failed: the next run marks it
  }
}

// The runs of the site still on Slurm: submitted, their reduce job still in the queue.
std::vector<std::pair<std::int64_t, std::string>> active_slurm_runs(SiteDb& db) {
  std::vector<std::pair<std::int64_t, std::string>> out;
  SiteDb::Statement s(db, "SELECT id, options FROM runs WHERE status = 'submitted'");
  while (s.step()) {
    std::string reduce;
    try {
      reduce = json::parse(s.text(1)).at("slurm").at("reduce_job").get<std::string>();
    } catch (const std::exception&) {
      continue;
    }
    if (slurm_job_active(reduce)) out.emplace_back(s.integer(0), reduce);
  }
  return out;
}

InputError slurm_run_pending(const fs::path& site, std::int64_t run, const std::string& job) {
  return InputError(site.string() + ": run " + std::to_string(run) +
                    " of this site is still on Slurm (its reduce job " + job +
                    " has not finished); --wait waits for it");
}

// The previous runs that did not end: 'running' ones were killed; 'submitted' ones whose
// reduce job left the queue without reducing were cancelled or failed. A submitted run still
// queued refuses this one.
void close_unfinished_runs(const fs::path& site, SiteDb& db) {
  const auto active = active_slurm_runs(db);
  if (!active.empty()) throw slurm_run_pending(site, active[0].first, active[0].second);
  SiteDb::Transaction t(db);
  db.exec("UPDATE runs SET status = 'interrupted' WHERE status IN ('running', 'submitted')");
  t.commit();
}

// Before the lock: a run on Slurm of this site makes this one wait (--wait) or refuses it.
void wait_for_slurm_runs(const fs::path& site, bool wait) {
  std::error_code ec;
  if (!fs::is_regular_file(site / "history.sqlite", ec)) return;
  while (true) {
    std::vector<std::pair<std::int64_t, std::string>> active;
    {
      SiteDb db(site / "history.sqlite");
      active = active_slurm_runs(db);
    }
    if (active.empty()) return;
    if (!wait) throw slurm_run_pending(site, active[0].first, active[0].second);
    wait_for_slurm_job(active[0].second);
  }
}

// The run of a site that the reduce job of run `run` finishes: its exit status, from the
// reduce.json it wrote (3 when it wrote none: see its log).
int slurm_run_exit_code(const fs::path& run_dir, std::ostream& err) {
  std::error_code ec;
  if (!fs::is_regular_file(run_dir / "reduce.json", ec)) {
    err << "nightly: the reduce job wrote no " << (run_dir / "reduce.json").string() << "; see "
        << (run_dir / "logs" / "reduce.out").string() << "\n";
    return kExitInternalError;
  }
  return read_json_file(run_dir / "reduce.json").at("exit_code").get<int>();
}

// Puts a report folder a Slurm task staged into the site: its files go into an OutputFolder's
// temporary folder, which is exchanged with the campaign's report folder in one rename.
void install_staged_report(const fs::path& staged, const fs::path& dest) {
  OutputFolder out(dest);
  for (const auto& e : fs::directory_iterator(staged)) {
    if (e.path().filename() == kManifestName) continue;
    fs::rename(e.path(), out.work() / e.path().filename());
  }
  out.commit();
  fs::remove_all(staged);
}

}  // namespace

int run_nightly(const fs::path& root, const fs::path& site, const NightlyOptions& options,
                std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  std::ostream& err = options.errors ? *options.errors : log;
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    throw InputError(root.string() + ": no such folder (the archive root)");
  }
  check_site(site, root);
  wait_for_slurm_runs(site, options.wait);
  // On Slurm, each task reports with the worker threads it was given (--cpus-per-task).
  const int jobs = options.slurm.enabled ? std::max(options.jobs, 1) : options.jobs;
  SlurmJobs submitted;
  fs::path run_dir;
  {
    SiteLock lock(site, options.wait);
    SiteDb db(site / "history.sqlite");
    fs::create_directories(site / "campaigns");

    const std::vector<ArchiveCampaign> found = find_campaigns(root, site);
    if (found.empty()) {
      // An unmounted share is an empty folder: its report folders must not leave the site.
      SiteDb::Statement s(db,
                          "SELECT r.id, COUNT(c.name) FROM runs r JOIN campaign_runs c ON "
                          "c.run_id = r.id WHERE r.id = (SELECT MAX(id) FROM runs WHERE status = "
                          "'done') GROUP BY r.id");
      if (s.step() && s.integer(1) > 0) {
        throw InputError(root.string() +
                         ": no campaign found under the archive root, but the site's last run (" +
                         std::to_string(s.integer(0)) + ") had " + std::to_string(s.integer(1)) +
                         ": is the archive mounted? Nothing was changed; to start over with an "
                         "empty archive, give a new --out");
      }
    }
    close_unfinished_runs(site, db);

    const std::string program = program_identity() + " jobs=" + std::to_string(jobs);
    const std::string started = utc_now();
    std::int64_t run_id = 0;
    {
      SiteDb::Transaction t(db);
      SiteDb::Statement s(db,
                          "INSERT INTO runs (started_utc, finished_utc, version, options, "
                          "runtime_s, status) VALUES (?, '', ?, ?, 0, 'running')");
      s.bind(1, started).bind(2, program);
      s.bind(3,
             json({{"pdf", options.pdf}, {"jobs", jobs}, {"slurm", options.slurm.enabled}}).dump());
      s.step();
      run_id = db.last_insert_id();
      t.commit();
    }

    try {
      const std::vector<CampaignPlan> plans =
          plan_campaigns(site, db, found, program, options.pdf, run_id);
      log << "nightly: " << plans.size() << " " << (plans.size() == 1 ? "campaign" : "campaigns")
          << " under " << root.string() << "\n";
      if (!options.slurm.enabled) {
        std::vector<CampaignState> states;
        std::vector<fs::path> remove_after_index;
        int exit_code = kExitOk;
        for (std::size_t i = 0; i < plans.size(); ++i) {
          const auto tc = std::chrono::steady_clock::now();
          const CampaignPlan& p = plans[i];
          const fs::path folder = site / "campaigns" / p.name;
          const json previous = previous_results(folder);
          CampaignState st;
          if (p.reusable) {
            st = finish_campaign(site, db, run_id, p, nullptr, nullptr, previous,
                                 options.tolerances, remove_after_index);
          } else {
            // Recomputed into a temporary folder that replaces its report folder; the tests
            // whose keys did not change are restored from the per-test cache.
            SiteResultCache cache(node_keys(p), stored_results(db, p.name));
            const ComputeOutcome o = compute_campaign(p.folder, folder, options.pdf, jobs, &cache);
            st = finish_campaign(site, db, run_id, p, &o, &cache, previous, options.tolerances,
                                 remove_after_index);
          }
          exit_code = with_campaign(exit_code, st);
          log_campaign(log, err, i, plans.size(), st, seconds_since(tc));
          states.push_back(std::move(st));
        }
        return write_site_index(root_label(root), site, db, run_id, started, seconds_since(t0),
                                options.pdf, states, remove_after_index, exit_code,
                                options.tolerances, jobs, log, err);
      }

      // --slurm: the plan and the job scripts into the site, a task per campaign to recompute.
      run_dir = slurm_run_dir(fs::absolute(site), run_id);
      fs::remove_all(run_dir, ec);
      fs::create_directories(run_dir);
      json tasks = json::array();
      json campaigns = json::array();
      for (const auto& p : plans) {
        campaigns.push_back(p.to_json());
        if (p.reusable) continue;
        tasks.push_back({{"name", p.name},
                         {"path", p.path},
                         {"folder", fs::absolute(p.folder).string()},
                         {"keys", node_keys(p)}});
        // The kinds' results the task may restore, beside the plan (a task does not open the
        // site's database: the nodes may not share its file locks).
        const auto stored = stored_results(db, p.name);
        if (!stored.empty()) {
          fs::create_directories(run_dir / "cache");
          write_file_checked(run_dir / "cache" / (p.name + ".bin"), to_bytes(stored));
        }
      }
      if (!options.tolerances_file.empty()) {
        fs::copy_file(options.tolerances_file, run_dir / "tolerances.yaml",
                      fs::copy_options::overwrite_existing);
      }
      const json plan = {
          {"format", "chatterlab-nightly-plan/1"},
          {"run", run_id},
          {"root", root_label(root)},
          {"started_utc", started},
          {"started_epoch_s",
           std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
                   .count() -
               seconds_since(t0)},
          {"pdf", options.pdf},
          {"jobs", jobs},
          {"tasks", tasks},
          {"campaigns", campaigns}};
      write_file_checked(run_dir / "plan.json", plan.dump(1) + "\n");
      const int task_count = static_cast<int>(tasks.size());
      write_slurm_scripts(fs::absolute(site), run_dir, run_id, task_count, jobs, options.slurm,
                          fs::read_symlink("/proc/self/exe"));
      submitted = submit_slurm_scripts(run_dir, task_count);
      {
        SiteDb::Transaction t(db);
        SiteDb::Statement s(db, "UPDATE runs SET status = 'submitted', options = ? WHERE id = ?");
        s.bind(1, json({{"pdf", options.pdf},
                        {"jobs", jobs},
                        {"slurm",
                         {{"array_job", submitted.array_id},
                          {"reduce_job", submitted.reduce_id},
                          {"tasks", task_count}}}})
                      .dump());
        s.bind(2, run_id);
        s.step();
        t.commit();
      }
      log << "nightly: run " << run_id << " submitted to Slurm: "
          << (task_count > 0
                  ? "array job " + submitted.array_id + " (" + std::to_string(task_count) + " " +
                        (task_count == 1 ? "task" : "tasks") + "), "
                  : std::string("no task (nothing changed), "))
          << "reduce job " << submitted.reduce_id << "; job scripts in " << run_dir.string()
          << "\n";
    } catch (...) {
      mark_failed(db, run_id);
      throw;
    }
  }  // the lock is released: the reduce job takes it
  if (!options.slurm.wait) return kExitOk;
  wait_for_slurm_job(submitted.reduce_id);
  return slurm_run_exit_code(run_dir, err);
}

int run_nightly_reduce(const fs::path& site, std::int64_t run, const NightlyOptions& options,
                       std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  std::ostream& err = options.errors ? *options.errors : log;
  const fs::path run_dir = slurm_run_dir(site, run);
  int exit_code = kExitOk;
  {
    SiteLock lock(site, /*wait=*/true);
    SiteDb db(site / "history.sqlite");
    {
      SiteDb::Statement s(db, "SELECT status FROM runs WHERE id = ?");
      s.bind(1, run);
      const std::string status = s.step() ? s.text(0) : std::string("absent");
      if (status != "submitted") {
        throw InputError(site.string() + ": run " + std::to_string(run) +
                         " is not waiting for its reduce job (status " + status +
                         "); nothing was changed");
      }
    }
    try {
      const json plan = read_json_file(run_dir / "plan.json");
      const bool pdf = plan.at("pdf").get<bool>();
      std::error_code ec;
      const CompareOptions tolerances = fs::is_regular_file(run_dir / "tolerances.yaml", ec)
                                            ? load_tolerances(run_dir / "tolerances.yaml")
                                            : options.tolerances;
      std::map<std::string, int> task_of;
      for (std::size_t i = 0; i < plan.at("tasks").size(); ++i) {
        task_of[plan["tasks"][i].at("name").get<std::string>()] = static_cast<int>(i);
      }
      std::vector<CampaignState> states;
      std::vector<fs::path> remove_after_index;
      const json& campaigns = plan.at("campaigns");
      for (std::size_t i = 0; i < campaigns.size(); ++i) {
        const auto tc = std::chrono::steady_clock::now();
        const CampaignPlan p = CampaignPlan::from_json(campaigns[i]);
        const fs::path folder = site / "campaigns" / p.name;
        const json previous = previous_results(folder);
        CampaignState st;
        if (p.reusable) {
          st = finish_campaign(site, db, run, p, nullptr, nullptr, previous, tolerances,
                               remove_after_index);
        } else {
          const fs::path staged = run_dir / "out" / p.name;
          const fs::path outcome_file = run_dir / "out" / (p.name + ".json");
          ComputeOutcome o;
          if (fs::is_regular_file(outcome_file, ec)) {
            o = ComputeOutcome::from_json(read_json_file(outcome_file));
          } else {
            o.internal = true;
            o.exit_code = kExitInternalError;
            o.errors = "the Slurm task of this campaign did not finish (task " +
                       std::to_string(task_of[p.name]) + "; see " + (run_dir / "logs").string() +
                       "/task-" + std::to_string(task_of[p.name]) + ".out)";
          }
          if (o.written) {
            try {
              install_staged_report(staged, folder);
            } catch (const std::exception& e) {
              o.written = false;
              o.internal = true;
              o.errors +=
                  std::string("the staged report could not be put into the site: ") + e.what();
            }
          }
          // What the task restored and computed, for the site's per-test cache.
          SiteResultCache cache(node_keys(p), stored_results(db, p.name));
          const fs::path cache_file = run_dir / "out" / (p.name + ".cache");
          if (o.written && fs::is_regular_file(cache_file, ec)) {
            TaskCache kept;
            try {
              from_bytes(read_file_bytes(cache_file), kept);
              cache.adopt(std::move(kept.kept), kept.restored);
            } catch (const InputError&) {  // damaged: nothing kept, computed next time
            }
          }
          st = finish_campaign(site, db, run, p, &o, &cache, previous, tolerances,
                               remove_after_index);
        }
        exit_code = with_campaign(exit_code, st);
        log_campaign(log, err, i, campaigns.size(), st, seconds_since(tc));
        states.push_back(std::move(st));
      }
      const double runtime =
          std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
              .count() -
          plan.at("started_epoch_s").get<double>();
      exit_code = write_site_index(
          plan.at("root").get<std::string>(), site, db, run,
          plan.at("started_utc").get<std::string>(), std::max(runtime, seconds_since(t0)), pdf,
          states, remove_after_index, exit_code, tolerances, plan.at("jobs").get<int>(), log, err);
      fs::remove_all(run_dir / "out", ec);
      fs::remove_all(run_dir / "cache", ec);
    } catch (...) {
      mark_failed(db, run);
      throw;
    }
  }
  write_file_checked(run_dir / "reduce.json", json({{"exit_code", exit_code}}).dump() + "\n");
  return exit_code;
}

}  // namespace chatterlab::app
