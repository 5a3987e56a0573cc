// The nightly site's database and lock (app/nightly/site_db.h): the schema version and its
// migration, a newer or foreign file refused with its name, transactions that a killed writer
// leaves rolled back, and the lock that keeps a second run off the site.
#include "app/nightly/site_db.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <memory>

#include "analysis/common/summary.h"
#include "render/temp_dir.h"

namespace chatterlab::app {
namespace {

std::int64_t count(SiteDb& db, const std::string& table) {
  SiteDb::Statement s(db, "SELECT COUNT(*) FROM " + table);
  EXPECT_TRUE(s.step());
  return s.integer(0);
}

void add_run(SiteDb& db, const std::string& version) {
  SiteDb::Statement s(db,
                      "INSERT INTO runs (started_utc, finished_utc, version, options, runtime_s, "
                      "status) VALUES ('2026-12-01T00:00:00Z', '2026-12-01T00:01:00Z', ?, '{}', "
                      "60, 'done')");
  s.bind(1, version);
  EXPECT_FALSE(s.step());
}

// Forks a child that runs `hold` (which takes a transaction or a lock), then tells the parent
// and waits to be killed; returns the child's pid once `hold` has returned.
template <class Hold>
pid_t child_holding(Hold&& hold) {
  int ready[2];
  if (::pipe(ready) != 0) return -1;
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(ready[0]);
    try {
      hold();
    } catch (...) {
      ::_exit(3);
    }
    const char c = 'x';
    if (::write(ready[1], &c, 1) != 1) ::_exit(2);
    ::pause();  // killed here, holding what `hold` took
    ::_exit(0);
  }
  ::close(ready[1]);
  char c = 0;
  const bool ok = child > 0 && ::read(ready[0], &c, 1) == 1;
  ::close(ready[0]);
  return ok ? child : -1;
}

// Kills the child with SIGKILL and says whether it died of it.
bool kill_child(pid_t child) {
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
}

TEST(SiteDb, ANewFileGetsTheCurrentSchemaAndKeepsItsRowsWhenReopened) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  {
    SiteDb db(file);
    EXPECT_EQ(db.schema_version(), SiteDb::kSchemaVersion);
    for (const char* t : {"runs", "campaign_runs", "test_cache", "trend_values"}) {
      EXPECT_EQ(count(db, t), 0) << t;
    }
    add_run(db, "0.1.0");
    SiteDb::Statement s(db, "INSERT INTO test_cache VALUES ('demo', 'tap/x', ?, ?, 1)");
    s.bind(1, std::string(64, 'a')).bind_blob(2, std::string("\0\1\2", 3));
    s.step();
  }
  SiteDb db(file);
  EXPECT_EQ(count(db, "runs"), 1);
  SiteDb::Statement s(db, "SELECT payload FROM test_cache WHERE test = 'tap/x'");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.blob(0), std::string("\0\1\2", 3));
}

TEST(SiteDb, ANewerSchemaOrAFileThatIsNotADatabaseIsRefusedByName) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  {
    SiteDb db(file);
    db.exec("PRAGMA user_version = " + std::to_string(SiteDb::kSchemaVersion + 1));
  }
  try {
    SiteDb db(file);
    FAIL() << "opened";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("history.sqlite"), std::string::npos) << m;
    EXPECT_NE(m.find("newer than this chatterlab's"), std::string::npos) << m;
  }
  const auto text = dir.path() / "notes.sqlite";
  std::ofstream(text) << "these are not the pages of a database, but plain text of some length\n";
  try {
    SiteDb db(text);
    FAIL() << "opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("notes.sqlite"), std::string::npos) << e.what();
  }
}

TEST(SiteDb, ATransactionLeftWithoutCommitIsRolledBack) {
  // A reopened file is not migrated again; a transaction left without commit (an exception
  // inside it) leaves nothing of what it did.
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  { SiteDb db(file); }
  SiteDb db(file);
  EXPECT_EQ(db.schema_version(), 1);
  EXPECT_EQ(SiteDb::migrations().size(), static_cast<std::size_t>(SiteDb::kSchemaVersion));
  {
    SiteDb::Transaction t(db);
    db.exec("CREATE TABLE scratch (x)");
    EXPECT_THROW(db.exec("CREATE TABLE scratch (x)"), std::runtime_error);
  }  // rolled back
  EXPECT_THROW(count(db, "scratch"), std::runtime_error);
}

TEST(SiteDb, AWriterKilledInsideATransactionLeavesThePreviousStateReadable) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  {
    SiteDb db(file);
    add_run(db, "committed");
  }
  // Kept alive in the child until it is killed.
  std::unique_ptr<SiteDb> open;
  const pid_t child = child_holding([&] {
    open = std::make_unique<SiteDb>(file);
    open->exec("BEGIN IMMEDIATE");
    for (int i = 0; i < 2000; ++i) add_run(*open, "uncommitted");
  });
  ASSERT_GT(child, 0);
  ASSERT_TRUE(kill_child(child));
  SiteDb db(file);
  EXPECT_EQ(count(db, "runs"), 1);
  SiteDb::Statement s(db, "SELECT version FROM runs");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.text(0), "committed");
  EXPECT_EQ(db.integrity_check(), "ok");
}

TEST(SiteLock, ASecondRunIsRefusedByNameAndAKilledHolderLeavesNoLock) {
  render::TempDir dir("sitelock");
  const auto site = dir.path() / "site";
  {
    SiteLock first(site, false);
    try {
      SiteLock second(site, false);
      FAIL() << "locked twice";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(
          m.find("is in use by another chatterlab nightly (process " + std::to_string(::getpid())),
          std::string::npos)
          << m;
      EXPECT_NE(m.find("--wait"), std::string::npos) << m;
    }
  }
  SiteLock again(site, false);  // released with its holder
  // A holder killed with SIGKILL releases the lock with its process.
  std::unique_ptr<SiteLock> held;
  const pid_t child =
      child_holding([&] { held = std::make_unique<SiteLock>(dir.path() / "other", false); });
  ASSERT_GT(child, 0);
  EXPECT_THROW(SiteLock(dir.path() / "other", false), InputError);
  ASSERT_TRUE(kill_child(child));
  EXPECT_NO_THROW(SiteLock(dir.path() / "other", false));
}

}  // namespace
}  // namespace chatterlab::app
