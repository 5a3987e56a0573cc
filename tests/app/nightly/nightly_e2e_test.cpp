// chatterlab nightly (app/nightly/nightly.h) on a small archive: two synthetic campaigns (one
// with a cut that uses the hammer modes) and one whose campaign.yaml cannot be read. First
// run, a run with nothing changed, a run after one test.yaml was touched, a deliberate change
// that must be flagged, a run killed mid-way and run again, and a second run refused while
// one holds the site.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <regex>
#include <thread>

#include "analysis/common/summary.h"
#include "app/core/format.h"
#include "app/core/hashing.h"
#include "app/nightly/cache_keys.h"
#include "app/nightly/history.h"
#include "app/nightly/nightly.h"
#include "app/nightly/site_db.h"
#include "app/report/document.h"
#include "render/temp_dir.h"
#include "tests/app/cli/run_binary.h"
#include "tests/app/nightly/nightly_archive.h"
#include "tests/support/expect_input_error.h"

namespace chatterlab::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void write_archive(const fs::path& root, const fs::path& scratch) {
  chatterlab::testing::write_nightly_archive(root, scratch);
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

std::vector<std::string> strings(const json& j) {
  std::vector<std::string> v;
  for (const auto& s : j) v.push_back(s.get<std::string>());
  return v;
}

// Sets an environment variable for a scope, then restores it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* v = std::getenv(name)) {
      had_ = true;
      old_ = v;
    }
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_) {
      ::setenv(name_, old_.c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

// A folder holding a `weasyprint` that always fails, to put first in PATH.
fs::path failing_weasyprint(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "weasyprint")
      << "#!/bin/sh\necho 'weasyprint: failing on purpose' >&2\nexit 1\n";
  fs::permissions(dir / "weasyprint", fs::perms::owner_all | fs::perms::group_read |
                                          fs::perms::group_exec | fs::perms::others_read |
                                          fs::perms::others_exec);
  return dir;
}

NightlyOptions quiet_options() {
  NightlyOptions o;
  o.pdf = false;
  o.jobs = 2;
  return o;
}

class Nightly : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new render::TempDir("nightly");
    write_archive(dir_->path() / "archive", dir_->path());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  // A copy of the archive for a test that edits it.
  static fs::path archive_copy(const std::string& name) {
    const fs::path to = dir_->path() / name;
    fs::copy(dir_->path() / "archive", to, fs::copy_options::recursive);
    return to;
  }
  static int run(const fs::path& root, const fs::path& site, std::string* log_text = nullptr) {
    std::ostringstream log, err;
    NightlyOptions o = quiet_options();
    o.errors = &err;
    const int rc = run_nightly(root, site, o, log);
    if (log_text) *log_text = log.str() + err.str();
    return rc;
  }
  static render::TempDir* dir_;
};
render::TempDir* Nightly::dir_ = nullptr;

TEST_F(Nightly, CacheKeysFollowTheTestsThatUseAValue) {
  const CampaignSpec c = load_campaign(dir_->path() / "archive" / "a");
  const CampaignKeys k = campaign_keys(c, "program");
  ASSERT_EQ(k.tests.size(), 6u);  // tap/x, tap/y, three dyno-slot tests, cuts/constant
  // The cut needs both hammer modes and the coefficients of the dyno-slot group.
  EXPECT_EQ(k.dependents.at("tap/x"), std::vector<std::string>{"cuts/constant"});
  EXPECT_EQ(k.dependents.at("dyno/f050"), std::vector<std::string>{"cuts/constant"});
  EXPECT_TRUE(k.dependents.at("cuts/constant").empty());
  ASSERT_EQ(k.groups.count("group:dyno-slot"), 1u);
  // Another program or another test.yaml changes exactly the keys that hold it.
  const CampaignKeys other = campaign_keys(c, "program 2");
  for (const auto& [t, key] : k.tests) EXPECT_NE(other.tests.at(t), key) << t;
  const fs::path copy = archive_copy("keys");
  std::ofstream(copy / "a" / "tap" / "y" / "test.yaml", std::ios::app) << "# touched\n";
  const CampaignKeys touched = campaign_keys(load_campaign(copy / "a"), "program");
  for (const auto& [t, key] : k.tests) {
    const bool changes = t == "tap/y" || t == "cuts/constant";
    EXPECT_EQ(touched.tests.at(t) != key, changes) << t;
  }
}

TEST_F(Nightly, FirstRunNoChangeAndOneTouchedTest) {
  const fs::path root = archive_copy("touch");
  const fs::path site = dir_->path() / "site-touch";
  std::string log;
  // broken/ cannot be read: exit 1, the other two run.
  ASSERT_EQ(run(root, site, &log), 1) << log;
  const json first = read_json(site / "nightly.json");
  EXPECT_EQ(first["format"], "chatterlab-nightly/1");
  ASSERT_EQ(first["campaigns"].size(), 3u);
  const json& a = first["campaigns"]["nightly-a"];
  EXPECT_EQ(a["path"], "a");
  EXPECT_EQ(a["status"], "ok");
  EXPECT_EQ(a["recomputed"].size(), 6u);
  EXPECT_TRUE(a["cached"].empty());
  EXPECT_EQ(a["results"], "campaigns/nightly-a/results.json");
  EXPECT_EQ(first["campaigns"]["nightly-b"]["recomputed"].size(), 5u);
  const json& broken = first["campaigns"]["broken"];
  // Its report says so, with no number; the index names campaign.yaml's error.
  EXPECT_EQ(broken["status"], "nothing-analysed");
  EXPECT_NE(broken["message"].get<std::string>().find("campaign.yaml"), std::string::npos)
      << broken;
  const std::string index = chatterlab::testing::file_text(site / "index.html");
  for (const char* s : {"campaigns/nightly-a/index.html", "campaigns/nightly-b/index.html",
                        "nothing-analysed", "fn_hz"}) {
    EXPECT_NE(index.find(s), std::string::npos) << s;
  }
  const json a_first = read_json(site / "campaigns/nightly-a/results.json");
  const std::string a_results = sha256_file(site / "campaigns/nightly-a/results.json");
  const auto a_time = fs::last_write_time(site / "campaigns/nightly-a/results.json");

  // Nothing changed: every test of a and b comes from the cache, their folders untouched.
  ASSERT_EQ(run(root, site, &log), 1) << log;
  const json second = read_json(site / "nightly.json");
  for (const char* c : {"nightly-a", "nightly-b"}) {
    EXPECT_TRUE(second["campaigns"][c]["recomputed"].empty()) << c;
    EXPECT_EQ(second["campaigns"][c]["cached"], first["campaigns"][c]["recomputed"]) << c;
    EXPECT_EQ(second["campaigns"][c]["last_change_utc"], first["campaigns"][c]["last_change_utc"]);
  }
  EXPECT_EQ(sha256_file(site / "campaigns/nightly-a/results.json"), a_results);
  EXPECT_EQ(fs::last_write_time(site / "campaigns/nightly-a/results.json"), a_time);

  // tap/x touched: exactly tap/x and the cut that uses its mode are recomputed, the other
  // tests of a are restored from the per-test cache; b stays cached; the results equal the
  // first run's, timings aside.
  std::ofstream(root / "a" / "tap" / "x" / "test.yaml", std::ios::app) << "# touched\n";
  ASSERT_EQ(run(root, site, &log), 1) << log;
  const json third = read_json(site / "nightly.json");
  EXPECT_EQ(strings(third["campaigns"]["nightly-a"]["changed"]),
            (std::vector<std::string>{"cuts/constant", "tap/x"}));
  EXPECT_EQ(strings(third["campaigns"]["nightly-a"]["recomputed"]),
            (std::vector<std::string>{"cuts/constant", "tap/x"}));
  EXPECT_EQ(strings(third["campaigns"]["nightly-a"]["cached"]),
            (std::vector<std::string>{"dyno/f050", "dyno/f100", "dyno/f150", "tap/y"}));
  EXPECT_TRUE(third["campaigns"]["nightly-b"]["recomputed"].empty());
  EXPECT_TRUE(third["campaigns"]["nightly-a"]["flags"].empty());
  CompareOptions exact;
  exact.fallback = {"*", 0, 0, false};
  exact.rules = {{"inputs_sha256.*", 0, 0, true}};  // the touched file's hash
  const Comparison same =
      compare_results(a_first, read_json(site / "campaigns/nightly-a/results.json"), exact);
  EXPECT_GT(same.numbers_compared, 100);
  for (const auto& ch : same.changes) ADD_FAILURE() << ch.key;
}

TEST_F(Nightly, ADeliberatelyChangedResultIsFlagged) {
  const fs::path root = archive_copy("flag");
  const fs::path site = dir_->path() / "site-flag";
  ASSERT_EQ(run(root, site), 1);
  // A force calibration 5 % off on one dyno-slot record moves the fitted coefficients.
  const fs::path yaml = root / "b" / "dyno" / "f100" / "test.yaml";
  std::string text = chatterlab::testing::file_text(yaml);
  text = std::regex_replace(text, std::regex("Fx: \\{scale: 1\\}"), "Fx: {scale: 1.05}");
  std::ofstream(yaml) << text;
  std::string log;
  EXPECT_EQ(run(root, site, &log), 1) << log;
  const json n = read_json(site / "nightly.json");
  const json& flags = n["campaigns"]["nightly-b"]["flags"];
  ASSERT_FALSE(flags.empty()) << n;
  // The record's own mean force and the group's edge coefficients moved.
  const std::vector<std::string> flagged = strings(flags);
  for (const char* key : {"tests.dyno/f100.mean_Ft_N", "groups.dyno-slot.Kte_N_m"}) {
    EXPECT_NE(std::find(flagged.begin(), flagged.end(), key), flagged.end()) << key << flags;
  }
  EXPECT_TRUE(n["campaigns"]["nightly-a"]["flags"].empty());
  EXPECT_NE(log.find("flagged"), std::string::npos) << log;

  // The same two nights from the site's history: the first run's results against the second's.
  using chatterlab::testing::quoted;
  using chatterlab::testing::run_chatterlab;
  auto r = run_chatterlab(
      "compare last-1 last --json --site " + quoted(site) + " --campaign nightly-b", dir_->path());
  EXPECT_EQ(r.status, 1) << r.err;
  const json table = json::parse(r.out);
  EXPECT_EQ(table["flags"].get<int>(), static_cast<int>(flags.size())) << r.out;
  // a was cached in the second run: its results are the first run's, nothing moved.
  r = run_chatterlab("compare 1 2 --site " + quoted(site) + " --campaign nightly-a", dir_->path());
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  // Every campaign at once: b's flags, under its name.
  r = run_chatterlab("compare 1 last --json --site " + quoted(site), dir_->path());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(json::parse(r.out)["changes"][0]["key"].get<std::string>().rfind("nightly-b.", 0), 0u)
      << r.out;
  r = run_chatterlab("compare last-5 last --site " + quoted(site), dir_->path());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("has no run last-5 (fewer finished runs)"), std::string::npos) << r.err;
  r = run_chatterlab("compare 1 2 --site " + quoted(site) + " --campaign nope", dir_->path());
  EXPECT_NE(r.err.find("has no results of campaign 'nope'"), std::string::npos) << r.err;
  r = run_chatterlab("compare 1 2 --site " + quoted(dir_->path()), dir_->path());
  EXPECT_NE(r.err.find("no history.sqlite (not a chatterlab nightly site)"), std::string::npos)
      << r.err;
}

TEST_F(Nightly, ASecondRunOnTheSiteIsRefusedWhileOneHoldsIt) {
  const fs::path site = dir_->path() / "site-lock";
  SiteLock held(site, false);
  try {
    run(dir_->path() / "archive", site);
    FAIL() << "ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is in use by another chatterlab nightly"),
              std::string::npos)
        << e.what();
  }
  // A folder that is not a site is never touched.
  const fs::path other = dir_->path() / "not-a-site";
  fs::create_directories(other);
  std::ofstream(other / "notes.txt") << "mine\n";
  const auto refused = [&](const fs::path& root, const fs::path& out) {
    try {
      run(root, out);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("ran");
  };
  EXPECT_NE(refused(dir_->path() / "archive", other).find("is not a chatterlab nightly site"),
            std::string::npos);
  EXPECT_EQ(chatterlab::testing::file_text(other / "notes.txt"), "mine\n");
  EXPECT_NE(refused(dir_->path() / "archive", dir_->path()).find("is the archive root or holds it"),
            std::string::npos);
  EXPECT_NE(refused(dir_->path() / "no-archive", dir_->path() / "site-none")
                .find("no-archive: no such folder (the archive root)"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir_->path() / "site-none"));
}

// Starts `chatterlab nightly` and kills it with SIGKILL as soon as it has finished its first
// campaign (inside the second), then runs it again to the end.
TEST_F(Nightly, ARunKilledMidWayLeavesAUsableSiteAndTheRerunCompletesIt) {
  using chatterlab::testing::quoted;
  const fs::path root = dir_->path() / "archive";
  const fs::path site = dir_->path() / "site-kill";
  const fs::path out = dir_->path() / "kill-stdout.txt";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string cmd = "exec " + quoted(CHATTERLAB_BINARY) + " nightly " + quoted(root) +
                            " --out " + quoted(site) + " --no-pdf --jobs 2 > " + quoted(out) +
                            " 2>&1";
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  bool first_done = false;
  for (int i = 0; i < 6000 && !first_done; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    first_done = chatterlab::testing::file_text(out).find("[1/3]") != std::string::npos;
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(first_done) << chatterlab::testing::file_text(out);
  ASSERT_TRUE(WIFSIGNALED(status)) << chatterlab::testing::file_text(out);
  {
    // The database is usable and the killed run is on record as not finished.
    SiteDb db(site / "history.sqlite");
    EXPECT_EQ(db.integrity_check(), "ok");
    SiteDb::Statement runs(db, "SELECT status FROM runs");
    ASSERT_TRUE(runs.step());
    EXPECT_EQ(runs.text(0), "running");
  }
  // No half-written report folder is in the campaigns' place.
  for (const auto& e : fs::directory_iterator(site / "campaigns")) {
    const std::string n = e.path().filename().string();
    if (n[0] == '.') continue;
    EXPECT_TRUE(fs::exists(e.path() / "results.json")) << n;
  }

  // The same program again (the cache keys hold the executable's hash).
  const auto rerun = chatterlab::testing::run_chatterlab(
      "nightly " + quoted(root) + " --out " + quoted(site) + " --no-pdf --jobs 2", dir_->path());
  ASSERT_EQ(rerun.status, 1) << rerun.out << rerun.err;
  const json n = read_json(site / "nightly.json");
  // a finished before the kill: cached now; b is computed.
  EXPECT_TRUE(n["campaigns"]["nightly-a"]["recomputed"].empty()) << n;
  EXPECT_EQ(n["campaigns"]["nightly-b"]["recomputed"].size(), 5u) << n;
  for (const char* c : {"nightly-a", "nightly-b"}) {
    EXPECT_EQ(n["campaigns"][c]["status"], "ok") << c;
    EXPECT_TRUE(fs::exists(site / "campaigns" / c / "index.html")) << c;
  }
  // Nothing of the killed run is left: only the report folders and their locks.
  for (const auto& e : fs::directory_iterator(site / "campaigns")) {
    const std::string name = e.path().filename().string();
    const bool lock = name.size() > 16 && name.substr(name.size() - 16) == ".chatterlab-lock";
    EXPECT_TRUE(name == "nightly-a" || name == "nightly-b" || name == "broken" || lock)
        << "left behind: " << name;
  }
  SiteDb db(site / "history.sqlite");
  SiteDb::Statement runs(db, "SELECT status FROM runs ORDER BY id");
  std::vector<std::string> statuses;
  while (runs.step()) statuses.push_back(runs.text(0));
  EXPECT_EQ(statuses, (std::vector<std::string>{"interrupted", "done"}));
}

// A campaign whose report.pdf could not be written exits 1 (as `report` does) and is recomputed
// the next night even though nothing changed; the site's report.pdf of an earlier run does not
// stay beside an index page whose PDF failed.
TEST_F(Nightly, AReportPdfNotWrittenExitsOneIsTriedAgainAndLeavesNoOldPdf) {
  const fs::path root = dir_->path() / "pdf-archive";
  fs::create_directories(root);
  fs::copy(dir_->path() / "archive" / "b", root / "b", fs::copy_options::recursive);
  const fs::path site = dir_->path() / "site-pdf";
  const fs::path bin = failing_weasyprint(dir_->path() / "failing-bin");
  const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "/usr/bin:/bin";
  const auto run_pdf = [&](bool failing, std::string* log_text) {
    std::unique_ptr<ScopedEnv> env;
    if (failing) env = std::make_unique<ScopedEnv>("PATH", bin.string() + ":" + path);
    std::ostringstream log, err;
    NightlyOptions o = quiet_options();
    o.pdf = true;
    o.errors = &err;
    const int rc = run_nightly(root, site, o, log);
    *log_text = log.str() + err.str();
    return rc;
  };
  std::string log;
  EXPECT_EQ(run_pdf(true, &log), 1) << log;
  json n = read_json(site / "nightly.json");
  EXPECT_EQ(n["campaigns"]["nightly-b"]["status"], "pdf-not-written") << n;
  EXPECT_NE(log.find("failing on purpose"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(site / "report.pdf"));
  EXPECT_FALSE(fs::exists(site / "campaigns" / "nightly-b" / "report.pdf"));

  // Nothing changed, but the campaign had no report.pdf: reported again, now with one; its
  // tests are restored from the per-test cache (no numerical work).
  EXPECT_EQ(run_pdf(false, &log), 0) << log;
  n = read_json(site / "nightly.json");
  EXPECT_EQ(n["campaigns"]["nightly-b"]["status"], "ok") << n;
  EXPECT_TRUE(n["campaigns"]["nightly-b"]["recomputed"].empty()) << n;
  EXPECT_EQ(n["campaigns"]["nightly-b"]["cached"].size(), 5u) << n;
  EXPECT_TRUE(fs::exists(site / "report.pdf"));
  EXPECT_TRUE(fs::exists(site / "campaigns" / "nightly-b" / "report.pdf"));

  // The campaign is complete and cached; the index's PDF fails: the old one is removed, exit 1.
  EXPECT_EQ(run_pdf(true, &log), 1) << log;
  n = read_json(site / "nightly.json");
  EXPECT_EQ(n["campaigns"]["nightly-b"]["status"], "ok") << n;
  EXPECT_TRUE(n["campaigns"]["nightly-b"]["recomputed"].empty()) << n;
  EXPECT_EQ(n["campaigns"]["nightly-b"]["cached"].size(), 5u) << n;
  EXPECT_TRUE(fs::exists(site / "index.html"));
  EXPECT_FALSE(fs::exists(site / "report.pdf"));
  EXPECT_TRUE(fs::exists(site / "campaigns" / "nightly-b" / "report.pdf"));
}

// A copy of the archive's campaign b alone, under `name`.
fs::path only_b(const fs::path& dir, const std::string& name) {
  const fs::path root = dir / name;
  fs::create_directories(root);
  fs::copy(dir / "archive" / "b", root / "b", fs::copy_options::recursive);
  return root;
}

// A campaign that cannot be read in a run (its report folder refused) has no results in that
// run's history: compare --site shows its numbers as removed, not an earlier night's numbers.
TEST_F(Nightly, AnUnreadableCampaignHasNoResultsInItsRun) {
  const fs::path root = only_b(dir_->path(), "unreadable-archive");
  const fs::path site = dir_->path() / "site-unreadable";
  std::string log;
  ASSERT_EQ(run(root, site, &log), 0) << log;
  // Not a report folder any more: the campaign's report cannot be put in its place.
  fs::remove_all(site / "campaigns" / "nightly-b");
  fs::create_directories(site / "campaigns" / "nightly-b");
  std::ofstream(site / "campaigns" / "nightly-b" / "notes.txt") << "not a report\n";
  EXPECT_EQ(run(root, site, &log), 1) << log;
  const json n = read_json(site / "nightly.json");
  const json& b = n["campaigns"]["nightly-b"];
  EXPECT_EQ(b["status"], "unreadable") << n;
  EXPECT_TRUE(b["recomputed"].empty()) << n;  // nothing was computed
  EXPECT_TRUE(b["cached"].empty()) << n;
  EXPECT_FALSE(b.contains("results")) << n;
  EXPECT_FALSE(fs::exists(site / "campaigns" / "nightly-b"));

  SiteDb db(site / "history.sqlite");
  EXPECT_TRUE(run_results(db, 1).contains("nightly-b"));
  EXPECT_FALSE(run_results(db, 2).contains("nightly-b")) << run_results(db, 2);
  try {
    run_results(db, 2, "nightly-b");
    FAIL() << "results of an unreadable campaign";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has no results of campaign 'nightly-b' (unreadable: "),
              std::string::npos)
        << e.what();
  }
  // Every value of the first run is gone in the second: each number is removed and flagged,
  // and so is each test's status "ok".
  const Comparison c = compare_results(run_results(db, 1), run_results(db, 2));
  ASSERT_GT(c.flags(), 100);
  int numbers = 0;
  for (const auto& ch : c.changes) {
    EXPECT_EQ(ch.key.rfind("nightly-b.", 0), 0u) << ch.key;
    EXPECT_TRUE(ch.b.is_null()) << ch.key;
    if (ch.a.is_number()) {
      ++numbers;
      EXPECT_EQ(ch.kind, Change::Kind::kRemoved) << ch.key;
      EXPECT_TRUE(ch.flag) << ch.key;
    }
  }
  EXPECT_GT(numbers, 100);
  const Change* status = nullptr;
  for (const auto& ch : c.changes) {
    if (ch.key == "nightly-b.tests.tap/x.status") status = &ch;
  }
  ASSERT_NE(status, nullptr);
  EXPECT_TRUE(status->flag);
}

// An exception other than bad input (here a report template that does not parse) is an
// internal error: exit 3, the previous report folder stays, and the next run recomputes it.
TEST_F(Nightly, AnInternalErrorKeepsThePreviousReportAndExitsThree) {
  const fs::path root = only_b(dir_->path(), "internal-archive");
  const fs::path site = dir_->path() / "site-internal";
  std::string log;
  ASSERT_EQ(run(root, site, &log), 0) << log;
  const std::string first = sha256_file(site / "campaigns" / "nightly-b" / "results.json");
  const fs::path templates = dir_->path() / "broken-templates";
  fs::copy(templates_dir(), templates, fs::copy_options::recursive);
  std::ofstream(templates / "report.html") << "{{#unclosed}}\n";
  std::ofstream(root / "b" / "tap" / "x" / "test.yaml", std::ios::app) << "# touched\n";
  {
    ScopedEnv env("CHATTERLAB_TEMPLATES", templates.string());
    EXPECT_EQ(run(root, site, &log), 3) << log;
  }
  json n = read_json(site / "nightly.json");
  EXPECT_EQ(n["campaigns"]["nightly-b"]["status"], "internal-error") << n;
  EXPECT_TRUE(n["campaigns"]["nightly-b"]["recomputed"].empty()) << n;
  EXPECT_NE(n["campaigns"]["nightly-b"]["message"].get<std::string>().find("INTERNAL ERROR"),
            std::string::npos)
      << n;
  EXPECT_EQ(sha256_file(site / "campaigns" / "nightly-b" / "results.json"), first);
  {
    SiteDb db(site / "history.sqlite");
    EXPECT_FALSE(run_results(db, 2).contains("nightly-b"));
  }
  // The templates are back: recomputed though nothing changed since.
  EXPECT_EQ(run(root, site, &log), 0) << log;
  n = read_json(site / "nightly.json");
  EXPECT_EQ(n["campaigns"]["nightly-b"]["status"], "ok") << n;
  EXPECT_EQ(n["campaigns"]["nightly-b"]["recomputed"].size(), 5u) << n;
}

// A campaign without tests: quick to run, its report says nothing was analysed.
void write_empty_campaign(const fs::path& folder, const std::string& name) {
  fs::create_directories(folder);
  std::ofstream(folder / "campaign.yaml")
      << "format: chatterlab-campaign/1\nname: " << name << "\n";
}

// A scan of the root that cannot complete is an error naming the root, and an archive that
// looks empty while the last run had campaigns (an unmounted share) is refused untouched.
TEST_F(Nightly, AnArchiveThatCannotBeScannedOrLooksEmptyIsRefused) {
  const fs::path missing = dir_->path() / "no-such-root";
  try {
    find_campaigns(missing);
    FAIL() << "scanned";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("no-such-root: the archive root cannot be read to the end"),
        std::string::npos)
        << e.what();
  }
  const fs::path root = dir_->path() / "vanishing";
  write_empty_campaign(root / "solo", "solo");
  const fs::path site = dir_->path() / "site-vanishing";
  EXPECT_EQ(run(root, site), 1);  // nothing analysed
  ASSERT_TRUE(fs::exists(site / "campaigns" / "solo" / "results.json"));
  fs::remove_all(root / "solo");
  try {
    run(root, site);
    FAIL() << "ran over an empty archive";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "no campaign found under the archive root, but the site's last run (1) had 1: "
                  "is the archive mounted?"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(site / "campaigns" / "solo" / "results.json"));
  SiteDb db(site / "history.sqlite");
  SiteDb::Statement runs(db, "SELECT COUNT(*) FROM runs");
  ASSERT_TRUE(runs.step());
  EXPECT_EQ(runs.integer(0), 1);
}

// Two campaigns of one name whose paths sanitize alike ("lab/a", "lab-a") get two folders.
TEST_F(Nightly, CampaignsWhosePathsSanitizeAlikeGetTwoFolders) {
  const fs::path root = dir_->path() / "alike";
  write_empty_campaign(root / "lab" / "a", "demo");
  write_empty_campaign(root / "lab-a", "demo");
  const fs::path site = dir_->path() / "site-alike";
  std::string log;
  EXPECT_EQ(run(root, site, &log), 1) << log;  // nothing analysed in either
  const json n = read_json(site / "nightly.json");
  const std::string slash = "demo@lab-a-" + sha256_text("lab/a").substr(0, 8);
  const std::string dash = "demo@lab-a-" + sha256_text("lab-a").substr(0, 8);
  ASSERT_EQ(n["campaigns"].size(), 2u) << n;
  EXPECT_EQ(n["campaigns"][slash]["path"], "lab/a") << n;
  EXPECT_EQ(n["campaigns"][dash]["path"], "lab-a") << n;
  EXPECT_TRUE(fs::exists(site / "campaigns" / slash / "results.json"));
  EXPECT_TRUE(fs::exists(site / "campaigns" / dash / "results.json"));
  EXPECT_EQ(run(root, site, &log), 1) << log;  // and again, with the history's rows
}

// An exception that ends the run (here: no index template) leaves it on record as failed.
TEST_F(Nightly, ARunEndedByAnExceptionIsRecordedAsFailed) {
  const fs::path root = dir_->path() / "no-index";
  write_empty_campaign(root / "solo", "solo");
  const fs::path templates = dir_->path() / "templates-without-index";
  fs::copy(templates_dir(), templates, fs::copy_options::recursive);
  fs::remove(templates / "nightly.html");
  const fs::path site = dir_->path() / "site-no-index";
  {
    ScopedEnv env("CHATTERLAB_TEMPLATES", templates.string());
    EXPECT_THROW(run(root, site), std::exception);
  }
  SiteDb db(site / "history.sqlite");
  SiteDb::Statement runs(db, "SELECT status, finished_utc FROM runs");
  ASSERT_TRUE(runs.step());
  EXPECT_EQ(runs.text(0), "failed");
  EXPECT_FALSE(runs.text(1).empty());
  EXPECT_FALSE(runs.step());
}

// campaign.yaml names "." and ".." are valid results.json names; in the site they become plain
// folders, so that nothing but the campaign's own folder is ever replaced or removed.
TEST_F(Nightly, ACampaignNamedDotOrDotDotGetsAPlainFolder) {
  const fs::path root = dir_->path() / "dots";
  for (const std::string n : {"up", "here"}) {
    fs::create_directories(root / n);
    std::ofstream(root / n / "campaign.yaml")
        << "format: chatterlab-campaign/1\nname: " << (n == "up" ? ".." : ".") << "\n";
  }
  const fs::path site = dir_->path() / "site-dots";
  EXPECT_EQ(run(root, site), 1);  // no test analysed in either
  EXPECT_TRUE(fs::exists(site / "history.sqlite"));
  const json n = read_json(site / "nightly.json");
  EXPECT_TRUE(n["campaigns"].contains("campaign-..")) << n;
  EXPECT_TRUE(n["campaigns"].contains("campaign-.")) << n;
  EXPECT_TRUE(fs::exists(site / "campaigns" / "campaign-.." / "results.json"));
  EXPECT_EQ(run(root, site), 1);
  EXPECT_TRUE(fs::exists(site / "history.sqlite"));
  EXPECT_TRUE(fs::exists(site / "campaigns" / "campaign-." / "results.json"));
}

// A --slurm run whose reduce job left the queue without reducing (cancelled, failed) is marked
// interrupted by the next run, and its reduce job, were it to start after all, changes nothing.
TEST_F(Nightly, ASlurmRunWhoseReduceJobIsGoneIsInterruptedAndItsReduceRefused) {
  const fs::path root = dir_->path() / "gone-reduce";
  write_empty_campaign(root / "solo", "solo");
  const fs::path site = dir_->path() / "site-gone-reduce";
  EXPECT_EQ(run(root, site), 1);  // nothing analysed
  {
    SiteDb db(site / "history.sqlite");
    db.exec(
        "UPDATE runs SET status = 'submitted', options = "
        "'{\"slurm\": {\"reduce_job\": \"999999999\"}}' WHERE id = 1");
  }
  EXPECT_EQ(run(root, site), 1);
  {
    SiteDb db(site / "history.sqlite");
    SiteDb::Statement s(db, "SELECT id, status FROM runs ORDER BY id");
    ASSERT_TRUE(s.step());
    EXPECT_EQ(s.text(1), "interrupted");
    ASSERT_TRUE(s.step());
    EXPECT_EQ(s.text(1), "done");
  }
  std::ostringstream log;
  chatterlab::testing::expect_input_error(
      [&] { run_nightly_reduce(site, 1, quiet_options(), log); },
      site.string() +
          ": run 1 is not waiting for its reduce job (status interrupted); nothing was changed");
  chatterlab::testing::expect_input_error(
      [&] { run_nightly_reduce(site, 7, quiet_options(), log); },
      site.string() +
          ": run 7 is not waiting for its reduce job (status absent); nothing was "
          "changed");
}

// The rows of the trend table of identified `key` in trends.html, each as its cells' text
// (tags removed).
std::vector<std::vector<std::string>> trend_rows(const std::string& page, const std::string& key) {
  std::vector<std::vector<std::string>> rows;
  const auto head = page.find("<th>" + key + "</th>");
  if (head == std::string::npos) return rows;
  const std::string table = page.substr(head, page.find("</table>", head) - head);
  const std::regex row("<tr>(.*?)</tr>");
  const std::regex cell("<td[^>]*>(.*?)</td>");
  const std::regex tag("<[^>]*>");
  for (auto r = std::sregex_iterator(table.begin(), table.end(), row); r != std::sregex_iterator();
       ++r) {
    const std::string text = (*r)[1].str();
    std::vector<std::string> cells;
    for (auto c = std::sregex_iterator(text.begin(), text.end(), cell); c != std::sregex_iterator();
         ++c) {
      cells.push_back(std::regex_replace((*c)[1].str(), tag, ""));
    }
    if (!cells.empty()) rows.push_back(cells);
  }
  return rows;
}

// A value of the cut moved (the displacement sensor's distance to the tool tip 5 % off): the
// trend page flags it "moved" in the second run; the database holds every estimator final of
// the cut as results.json has it; the comparison page lists every variant.
TEST_F(Nightly, TrendPagesFlagAMovedValueAndTheDatabaseHoldsTheEstimatorFinals) {
  const fs::path root = archive_copy("trends");
  const fs::path site = dir_->path() / "site-trends";
  std::string log;
  ASSERT_EQ(run(root, site, &log), 1) << log;  // broken/ cannot be read
  const json first = read_json(site / "campaigns/nightly-a/results.json");
  const fs::path yaml = root / "a" / "cuts" / "constant" / "test.yaml";
  std::string text = chatterlab::testing::file_text(yaml);
  text = std::regex_replace(text, std::regex("sensor_to_tip: 2.78"), "sensor_to_tip: 2.92");
  std::ofstream(yaml) << text;
  ASSERT_EQ(run(root, site, &log), 1) << log;
  const json second = read_json(site / "campaigns/nightly-a/results.json");
  const double m1 = first["identified"]["m_kg"].get<double>();
  const double m2 = second["identified"]["m_kg"].get<double>();
  ASSERT_NE(m1, m2);

  // a and b share their tool (2 teeth, radius 6.35 mm): one series; broken/ has none.
  ASSERT_TRUE(fs::exists(site / "trends.html"));
  const std::string page = chatterlab::testing::file_text(site / "trends.html");
  EXPECT_NE(page.find("<h2>2 teeth, r 6.35 mm</h2>\n<p>Campaigns: nightly-a, nightly-b.</p>"),
            std::string::npos);
  EXPECT_NE(page.find("<h2>broken</h2>\n<p>Campaigns: broken.</p>"), std::string::npos);
  const auto rows = trend_rows(page, "m_kg");
  ASSERT_EQ(rows.size(), 2u) << page;
  EXPECT_EQ(rows[0][0], "1");
  EXPECT_EQ(rows[0][2], "nightly-a");
  EXPECT_EQ(rows[0][3], fmt_sig(m1, 6));
  EXPECT_EQ(rows[0][5], "");
  EXPECT_EQ(rows[1][0], "2");
  EXPECT_EQ(rows[1][3], fmt_sig(m2, 6));
  EXPECT_EQ(rows[1][4], "[" + fmt_sig(second["identified"]["m_kg_ci95"][0].get<double>(), 5) +
                            ", " + fmt_sig(second["identified"]["m_kg_ci95"][1].get<double>(), 5) +
                            "]");
  EXPECT_EQ(rows[1][5], "moved");
  EXPECT_NE(page.find("nightly-a: <code>m_kg</code> moved"), std::string::npos);  // this run's
  EXPECT_TRUE(fs::exists(site / "figures" / "trend-1-m_kg.svg"));
  EXPECT_TRUE(fs::exists(site / "figures" / "trend-1-m_kg.png"));
  const std::string index = chatterlab::testing::file_text(site / "index.html");
  EXPECT_NE(index.find("href=\"trends.html\""), std::string::npos);
  EXPECT_NE(index.find("href=\"estimators.html\""), std::string::npos);

  // The database: the identified values with their intervals, and each estimator final.
  SiteDb db(site / "history.sqlite");
  SiteDb::Statement s(db,
                      "SELECT value, lo, hi FROM trend_values WHERE run_id = 2 AND campaign = "
                      "'nightly-a' AND key = ?");
  s.bind(1, std::string("m_kg"));
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.real(0), m2);
  EXPECT_EQ(s.real(1), second["identified"]["m_kg_ci95"][0].get<double>());
  EXPECT_EQ(s.real(2), second["identified"]["m_kg_ci95"][1].get<double>());
  const json& estimators = second["tests"]["cuts/constant"]["estimators"];
  ASSERT_EQ(estimators.size(), 13u);
  int finals = 0;
  for (auto v = estimators.begin(); v != estimators.end(); ++v) {
    for (auto k = (*v)["estimates"].begin(); k != (*v)["estimates"].end(); ++k) {
      const std::string key = "cuts/constant/" + v.key() + "/" + k.key();
      s.reset();
      s.bind(1, key);
      ASSERT_TRUE(s.step()) << key;
      EXPECT_EQ(s.real(0), k->get<double>()) << key;
      EXPECT_TRUE(s.is_null(1)) << key;  // a final has no interval
      EXPECT_TRUE(s.is_null(2)) << key;
      ++finals;
    }
  }
  // 2 x (3 + 3 + 2 + 2) modal, 2 x 2 one-pair and 3 x 4 per-tooth coefficients
  EXPECT_EQ(finals, 36);
  SiteDb::Statement count(db,
                          "SELECT COUNT(*) FROM trend_values WHERE run_id = 2 AND campaign = "
                          "'nightly-a' AND key LIKE 'cuts/%'");
  ASSERT_TRUE(count.step());
  EXPECT_EQ(count.integer(0), finals);

  // The comparison page: one row per variant of the cut, with its final estimates.
  const std::string cmp = chatterlab::testing::file_text(site / "estimators.html");
  for (auto v = estimators.begin(); v != estimators.end(); ++v) {
    const std::string row = "<td><code>cuts/constant</code></td><td>" + v.key() + "</td>";
    EXPECT_NE(cmp.find(row), std::string::npos) << v.key();
  }
  EXPECT_NE(cmp.find("m_kg = " +
                     fmt_sig(estimators["ekf-modal-x"]["estimates"]["m_kg"].get<double>(), 6)),
            std::string::npos);
  EXPECT_TRUE(fs::exists(site / "figures" / "estimators-1.svg"));
}

// A ci95 end that is not a number (null in results.json) stays NULL in trend_values and shows
// as n/a; a run of another program than the previous one's is flagged "program changed".
TEST_F(Nightly, ANullIntervalEndStaysNullAndAChangedProgramIsFlagged) {
  const fs::path root = dir_->path() / "trends-null";
  fs::create_directories(root);
  fs::copy(dir_->path() / "archive" / "a", root / "a", fs::copy_options::recursive);
  const fs::path site = dir_->path() / "site-trends-null";
  std::string log;
  ASSERT_EQ(run(root, site, &log), 0) << log;
  // The stored results with an interval end made null, recorded as the run's, so that the next
  // run takes them from the cache; and the first run's program made another.
  const fs::path results = site / "campaigns" / "nightly-a" / "results.json";
  json r = read_json(results);
  const double c = r["identified"]["c_kg_s"].get<double>();
  const double lo = r["identified"]["c_kg_s_ci95"][0].get<double>();
  r["identified"]["c_kg_s_ci95"][1] = nullptr;
  write_results_json(results, r);
  {
    SiteDb db(site / "history.sqlite");
    SiteDb::Statement u(db, "UPDATE campaign_runs SET results_sha256 = ? WHERE run_id = 1");
    u.bind(1, sha256_file(results));
    u.step();
    db.exec("UPDATE runs SET version = 'an older chatterlab' WHERE id = 1");
  }
  ASSERT_EQ(run(root, site, &log), 0) << log;
  EXPECT_TRUE(read_json(site / "nightly.json")["campaigns"]["nightly-a"]["recomputed"].empty());
  SiteDb db(site / "history.sqlite");
  SiteDb::Statement s(db,
                      "SELECT value, lo, hi FROM trend_values WHERE run_id = 2 AND campaign = "
                      "'nightly-a' AND key = 'c_kg_s'");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.real(0), c);
  EXPECT_EQ(s.real(1), lo);
  EXPECT_TRUE(s.is_null(2));
  const auto rows = trend_rows(chatterlab::testing::file_text(site / "trends.html"), "c_kg_s");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][4], "[" + fmt_sig(lo, 5) + ", n/a]");
  EXPECT_EQ(rows[1][5], "program changed");  // the same value: not moved
}

}  // namespace
}  // namespace chatterlab::app
