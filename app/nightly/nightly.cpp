#include "app/nightly/nightly.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "analysis/common/summary.h"
#include "app/cli/exit_codes.h"
#include "app/cli/output_folder.h"
#include "app/cli/progress.h"
#include "app/core/checked_write.h"
#include "app/core/format.h"
#include "app/core/hashing.h"
#include "app/git_commit.h"
#include "app/nightly/cache_keys.h"
#include "app/nightly/site_db.h"
#include "app/report/document.h"
#include "app/report/report.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

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
};

json headline_values(const json& results) {
  json rows = json::array();
  if (!results.is_object()) return rows;
  const auto it = results.find("identified");
  if (it == results.end() || !it->is_object()) return rows;
  for (auto v = it->begin(); v != it->end(); ++v) {
    if (!v->is_number() || v.key().find("_over_k") != std::string::npos) continue;
    json row = {{"key", v.key()}, {"value", v->get<double>()}};
    if (const auto ci = it->find(v.key() + "_ci95"); ci != it->end() && ci->is_array()) {
      row["ci95"] = *ci;
    }
    rows.push_back(row);
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

// The run after its row in `runs` was written: every campaign, the index and nightly.json.
int nightly_campaigns(const fs::path& root, const fs::path& site, const NightlyOptions& options,
                      std::ostream& log, SiteDb& db, const std::vector<ArchiveCampaign>& found,
                      const std::string& program, const std::string& started, std::int64_t run_id,
                      std::chrono::steady_clock::time_point t0);

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

int run_nightly(const fs::path& root, const fs::path& site, const NightlyOptions& options,
                std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    throw InputError(root.string() + ": no such folder (the archive root)");
  }
  check_site(site, root);
  SiteLock lock(site, options.wait);
  SiteDb db(site / "history.sqlite");
  fs::create_directories(site / "campaigns");

  const std::vector<ArchiveCampaign> found = find_campaigns(root, site);
  if (found.empty()) {
    // An unmounted share is an empty folder: its report folders must not leave the site.
    SiteDb::Statement s(db,
                        "SELECT r.id, COUNT(c.name) FROM runs r JOIN campaign_runs c ON c.run_id "
                        "= r.id WHERE r.id = (SELECT MAX(id) FROM runs WHERE status = 'done') "
                        "GROUP BY r.id");
    if (s.step() && s.integer(1) > 0) {
      throw InputError(root.string() +
                       ": no campaign found under the archive root, but the site's "
                       "last run (" +
                       std::to_string(s.integer(0)) + ") had " + std::to_string(s.integer(1)) +
                       ": is the archive mounted? Nothing was changed; to start over with an "
                       "empty archive, give a new --out");
    }
  }

  const std::string program = program_identity() + " jobs=" + std::to_string(options.jobs);
  const std::string started = utc_now();
  std::int64_t run_id = 0;
  {
    SiteDb::Transaction t(db);
    db.exec("UPDATE runs SET status = 'interrupted' WHERE status = 'running'");
    SiteDb::Statement s(db,
                        "INSERT INTO runs (started_utc, finished_utc, version, options, runtime_s, "
                        "status) VALUES (?, '', ?, ?, 0, 'running')");
    s.bind(1, started).bind(2, program).bind(3, json({{"pdf", options.pdf}}).dump());
    s.step();
    run_id = db.last_insert_id();
    t.commit();
  }

  try {
    return nightly_campaigns(root, site, options, log, db, found, program, started, run_id, t0);
  } catch (...) {
    // The run is on record as failed, not as running (the exception goes on to the caller).
    try {
      SiteDb::Transaction t(db);
      SiteDb::Statement s(db, "UPDATE runs SET finished_utc = ?, status = 'failed' WHERE id = ?");
      s.bind(1, utc_now()).bind(2, run_id);
      s.step();
      t.commit();
    } catch (const std::exception&) {  // the database itself failed: the next run marks it
    }
    throw;
  }
}

namespace {

int nightly_campaigns(const fs::path& root, const fs::path& site, const NightlyOptions& options,
                      std::ostream& log, SiteDb& db, const std::vector<ArchiveCampaign>& found,
                      const std::string& program, const std::string& started, std::int64_t run_id,
                      std::chrono::steady_clock::time_point t0) {
  std::ostream& err = options.errors ? *options.errors : log;
  std::error_code ec;
  std::vector<CampaignSpec> specs;
  std::vector<std::string> names;
  for (const auto& a : found) {
    specs.push_back(load_campaign(a.folder));
    names.push_back(results_campaign_name(specs.back()));
  }
  const std::map<std::string, std::string> site_name = site_names(found, names);
  log << "nightly: " << found.size() << " campaigns under " << root.string() << "\n";

  std::vector<CampaignState> states;
  std::vector<fs::path> remove_after_index;  // report folders of campaigns that did not run
  int exit_code = kExitOk;
  for (std::size_t i = 0; i < found.size(); ++i) {
    const auto tc = std::chrono::steady_clock::now();
    const ArchiveCampaign& a = found[i];
    CampaignState st;
    st.path = a.path;
    st.name = site_name.at(a.path);
    const fs::path folder = site / "campaigns" / st.name;
    CampaignKeys keys;
    // Keys that cannot be made (a broken invariant) make the campaign's key new in every run.
    std::string unkeyed;
    try {
      keys = campaign_keys(specs[i], program);
    } catch (const std::exception& e) {
      keys = {};
      unkeyed = "unkeyed in run " + std::to_string(run_id) + ": " + e.what() + "\n";
    }
    // The program and campaign.yaml as well, for a campaign without tests.
    std::string campaign_key_text =
        "pdf=" + std::to_string(options.pdf) + "\nprogram " + program + "\n";
    try {
      campaign_key_text += "campaign.yaml " + sha256_file(a.folder / "campaign.yaml") + "\n";
    } catch (const InputError&) {
      campaign_key_text += "campaign.yaml unreadable\n";
    }
    campaign_key_text += unkeyed;
    for (const auto& [t, k] : keys.tests) campaign_key_text += t + " " + k + "\n";
    for (const auto& [g, k] : keys.groups) campaign_key_text += g + " " + k + "\n";
    const std::string campaign_key = sha256_text(campaign_key_text);

    // The previous run's state of this campaign.
    std::map<std::string, std::string> stored;
    {
      SiteDb::Statement s(db, "SELECT test, key_sha256 FROM test_cache WHERE campaign = ?");
      s.bind(1, st.name);
      while (s.step()) stored[s.text(0)] = s.text(1);
    }
    std::string prev_key, prev_results_sha, prev_change, prev_status, prev_message;
    {
      SiteDb::Statement s(db,
                          "SELECT campaign_key, results_sha256, last_change_utc, status, message "
                          "FROM campaign_runs WHERE name = ? ORDER BY run_id DESC LIMIT 1");
      s.bind(1, st.name);
      if (s.step()) {
        prev_key = s.text(0);
        prev_results_sha = s.text(1);
        prev_change = s.text(2);
        prev_status = s.text(3);
        prev_message = s.text(4);
      }
    }
    for (const auto& [t, k] : keys.tests) {
      const auto it = stored.find(t);
      if (it == stored.end() || it->second != k) st.changed.push_back(t);
    }
    const fs::path results_file = folder / "results.json";
    bool failed = false;          // no report of this run: no keys kept, never reused
    bool recomputed_now = false;  // a new report folder is in place, its results recorded
    // Only a campaign whose last report was complete is left as it is: a missing report.pdf or
    // an internal error is tried again in every run.
    const bool reusable = (prev_status == "ok" || prev_status == "nothing-analysed") &&
                          !prev_key.empty() && prev_key == campaign_key &&
                          fs::is_regular_file(results_file, ec) &&
                          sha256_file(results_file) == prev_results_sha;
    json previous;
    if (fs::is_regular_file(results_file, ec)) {
      try {
        previous = read_json_file(results_file);
      } catch (const InputError&) {
        previous = nullptr;
      }
    }
    if (reusable) {
      for (const auto& [t, k] : keys.tests) st.cached.push_back(t);
      st.last_change_utc = prev_change;
      st.results = previous;
      st.status = prev_status;
      st.message = prev_message;
      st.exit_code = campaign_exit_code(st.status);
    } else {
      // Recompute the campaign into a temporary folder that replaces its report folder.
      std::ostringstream run_log, run_err;
      ReportOptions ro;
      ro.pdf = options.pdf;
      ro.jobs = options.jobs;
      ro.errors = &run_err;
      bool written = false;
      ro.before_writing = [&written] { written = true; };
      int rc = kExitInputError;
      bool committed = false;  // a new report folder is in place
      bool internal = false;   // stopped on an exception other than bad input
      try {
        OutputFolder out(folder);
        rc = run_report(a.folder, out.work(), ro, run_log);
        if (written) {
          out.commit();
          committed = true;
        }
      } catch (const InputError& e) {
        run_err << e.what() << "\n";
      } catch (const std::exception& e) {
        run_err << "INTERNAL ERROR: " << e.what() << "\n";
        internal = true;
      }
      st.last_change_utc = utc_now();
      // The campaign's own errors first (a campaign.yaml that does not parse), then the run's.
      for (const auto& e : specs[i].errors) st.message += e + "\n";
      st.message += run_err.str();
      while (!st.message.empty() && st.message.back() == '\n') st.message.pop_back();
      if (internal) {
        // A bug, a figure or template error, a lock or commit that failed: the previous report
        // folder stays as it was (OutputFolder removes its temporary folder); nothing was
        // computed, and the campaign is tried again in the next run.
        st.status = "internal-error";
        failed = true;
      } else if (!committed) {
        st.status = "unreadable";
        failed = true;
        // No report shows numbers of a campaign that did not run (removed once the index is
        // in place).
        remove_after_index.push_back(folder);
      } else {
        for (const auto& [t, k] : keys.tests) st.recomputed.push_back(t);
        recomputed_now = true;
        st.status = rc == kExitOk                ? "ok"
                    : rc == kExitInternalError   ? "internal-error"
                    : rc == kExitNothingAnalysed ? "nothing-analysed"
                                                 : "pdf-not-written";
        st.results = read_json_file(results_file);
        if (previous.is_object()) {
          const Comparison c = compare_results(previous, st.results, options.tolerances);
          for (const auto& ch : c.changes) {
            if (!ch.flag) continue;
            st.flags.push_back(ch.key);
          }
        }
      }
      st.exit_code = campaign_exit_code(st.status);
    }
    if (!st.flags.empty() && st.exit_code == kExitOk) st.exit_code = kExitFlagged;
    if (st.exit_code == kExitInternalError || exit_code == kExitOk) {
      exit_code = std::max(exit_code, st.exit_code);
    }

    // The history: this campaign's keys, its state and its values, in one transaction.
    {
      SiteDb::Transaction t(db);
      SiteDb::Statement del(db, "DELETE FROM test_cache WHERE campaign = ?");
      del.bind(1, st.name);
      del.step();
      if (!failed) {
        SiteDb::Statement put(db, "INSERT INTO test_cache VALUES (?, ?, ?, ?, ?)");
        for (const auto& [test, key] : keys.tests) {
          json entry;
          const json& results = st.results;  // read only: no "tests": null inserted
          if (const auto tests = results.is_object() ? results.find("tests") : results.end();
              tests != results.end() && tests->is_object()) {
            if (const auto it = tests->find(test); it != tests->end()) entry = *it;
          }
          put.reset();
          put.bind(1, st.name).bind(2, test).bind(3, key).bind_blob(4, entry.dump());
          put.bind(5, run_id);
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
      row.bind(10, failed ? std::string() : campaign_key);
      const bool has_results = fs::is_regular_file(results_file, ec);
      row.bind(11, has_results ? sha256_file(results_file) : std::string());
      if (recomputed_now && st.results.is_object()) {
        row.bind_blob(12, st.results.dump());
      } else {
        row.bind_null(12);
      }
      row.step();
      SiteDb::Statement val(db, "INSERT INTO trend_values VALUES (?, ?, ?, ?, ?, ?)");
      for (const auto& v : headline_values(st.results)) {
        val.reset();
        val.bind(1, run_id).bind(2, st.name).bind(3, v["key"].get<std::string>());
        val.bind(4, v["value"].get<double>());
        if (v.contains("ci95")) {
          val.bind(5, v["ci95"][0].is_number() ? v["ci95"][0].get<double>() : 0.0);
          val.bind(6, v["ci95"][1].is_number() ? v["ci95"][1].get<double>() : 0.0);
        } else {
          val.bind_null(5).bind_null(6);
        }
        val.step();
      }
      t.commit();
    }
    log << "[" << (i + 1) << "/" << found.size() << "] " << st.path << " (" << st.name
        << "): " << st.status << ", " << st.recomputed.size() << " recomputed, " << st.cached.size()
        << " cached";
    if (!st.flags.empty()) log << ", " << st.flags.size() << " flagged";
    log << ", " << format_duration(seconds_since(tc)) << std::endl;
    if (!st.message.empty() && st.status != "ok")
      err << "nightly: " << st.path << ": " << st.message << "\n";
    states.push_back(std::move(st));
  }

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
  const double runtime = seconds_since(t0);
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
      if (v.contains("ci95") && v["ci95"][0].is_number() && v["ci95"][1].is_number()) {
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
              {"root", root.filename().empty() ? root.parent_path().filename().string()
                                               : root.filename().string()},
              {"campaign_count", states.size()},
              {"runtime", format_duration(runtime)},
              {"campaigns", rows}};
  std::ostringstream doc_log;
  DocumentOptions dopt;
  dopt.pdf = options.pdf;
  const bool pdf_written = write_documents("nightly.html", ctx, stage, dopt, "nightly", doc_log);
  if (options.pdf && !pdf_written) {
    err << doc_log.str();
    exit_code = std::max(exit_code, static_cast<int>(kExitInputError));
  }
  // No report.pdf of an earlier run beside this run's index page.
  if (!pdf_written) fs::remove(site / "report.pdf", ec);
  for (const char* f : {"report.css", "index.html", "report.pdf", "nightly.json"}) {
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
  log << "nightly: " << states.size() << " campaigns in " << format_duration(runtime) << "; wrote "
      << (site / "index.html").string() << ", nightly.json\n";
  return exit_code;
}

}  // namespace
}  // namespace chatterlab::app
