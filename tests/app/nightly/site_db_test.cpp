// The nightly site's database and lock (app/nightly/site_db.h): the schema version and its
// migration, a newer or foreign file refused with its name, transactions that a killed writer
// leaves rolled back, and the lock that keeps a second run off the site.
#include "app/nightly/site_db.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

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
                      "INSERT INTO runs (started_utc, finished_utc, version, options, runtime_s) "
                      "VALUES ('2026-12-01T00:00:00Z', '2026-12-01T00:01:00Z', ?, '{}', 60)");
  s.bind(1, version);
  EXPECT_FALSE(s.step());
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
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(ready[0]);
    SiteDb db(file);
    db.exec("BEGIN IMMEDIATE");
    for (int i = 0; i < 2000; ++i) add_run(db, "uncommitted");
    const char c = 'x';
    if (::write(ready[1], &c, 1) != 1) ::_exit(2);
    ::pause();  // killed here, mid-transaction
    ::_exit(0);
  }
  ::close(ready[1]);
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  SiteDb db(file);
  EXPECT_EQ(count(db, "runs"), 1);
  SiteDb::Statement s(db, "SELECT version FROM runs");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.text(0), "committed");
  SiteDb::Statement check(db, "PRAGMA integrity_check");
  ASSERT_TRUE(check.step());
  EXPECT_EQ(check.text(0), "ok");
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
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(ready[0]);
    try {
      SiteLock held(dir.path() / "other", false);
      const char c = 'x';
      if (::write(ready[1], &c, 1) != 1) ::_exit(2);
      ::pause();
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(0);
  }
  ::close(ready[1]);
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_THROW(SiteLock(dir.path() / "other", false), InputError);
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_NO_THROW(SiteLock(dir.path() / "other", false));
}

}  // namespace
}  // namespace chatterlab::app
