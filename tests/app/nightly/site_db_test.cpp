// The nightly site's database and lock (app/nightly/site_db.h): the schema version and its
// migration (once, when two processes open a new file at once), a newer or foreign file refused
// with its name and closed, failures that name their SQL, transactions that a killed writer
// leaves rolled back, and the lock that keeps a second run off the site.
#include "app/nightly/site_db.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "analysis/common/summary.h"
#include "render/temp_dir.h"
#include "tests/support/expect_input_error.h"

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

// Forks a child that runs `body` and exits: 0 when it returned, 3 when it threw (its message on
// stderr). The child starts `body` when the pipe `go` reaches its end (once the parent closes
// its write end), so that several children start together.
pid_t child_running(const int go[2], const std::function<void()>& body) {
  const pid_t child = ::fork();
  if (child != 0) return child;
  ::close(go[1]);
  char c = 0;
  if (::read(go[0], &c, 1) < 0) ::_exit(2);
  try {
    body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "child: %s\n", e.what());
    ::_exit(3);
  }
  ::_exit(0);
}

// Waits for a child and returns its exit status (-1: it did not exit normally).
int exit_status(pid_t child) {
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The message of the std::runtime_error that `f` throws ("" when it throws none).
std::string runtime_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// The file's bytes.
std::string bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// How many file descriptors this process holds: a sqlite3 handle left open keeps one.
std::size_t open_descriptors() {
  std::size_t n = 0;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd");
       it != std::filesystem::directory_iterator(); ++it) {
    ++n;
  }
  return n;
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
    SiteDb::Statement s(db,
                        "INSERT INTO test_cache (campaign, test, key_sha256, payload, run_id) "
                        "VALUES ('demo', 'tap/x', ?, ?, 1)");
    s.bind(1, std::string(64, 'a')).bind_blob(2, std::string("\0\1\2", 3));
    s.step();
  }
  SiteDb db(file);
  EXPECT_EQ(count(db, "runs"), 1);
  SiteDb::Statement s(db, "SELECT payload FROM test_cache WHERE test = 'tap/x'");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.blob(0), std::string("\0\1\2", 3));
}

// A site written by the version-1 program (no kind results in its test cache) is migrated in
// place: its rows stay, the column is added, empty.
TEST(SiteDb, AVersionOneFileIsMigratedKeepingItsRows) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  {
    SiteDb db(file);
    add_run(db, "0.1.0");
    db.exec(
        "INSERT INTO test_cache (campaign, test, key_sha256, payload, run_id) VALUES ('demo', "
        "'tap/x', 'k', 'null', 1)");
    db.exec("ALTER TABLE test_cache DROP COLUMN result; PRAGMA user_version = 1");
    EXPECT_EQ(db.schema_version(), 1);
  }
  SiteDb db(file);
  EXPECT_EQ(db.schema_version(), 2);
  SiteDb::Statement s(db, "SELECT test, key_sha256, result IS NULL FROM test_cache");
  ASSERT_TRUE(s.step());
  EXPECT_EQ(s.text(0), "tap/x");
  EXPECT_EQ(s.text(1), "k");
  EXPECT_EQ(s.integer(2), 1);
  EXPECT_EQ(count(db, "runs"), 1);
}

TEST(SiteDb, ANewerSchemaOrAFileThatIsNotADatabaseIsRefusedByName) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  {
    SiteDb db(file);
    db.exec("PRAGMA user_version = " + std::to_string(SiteDb::kSchemaVersion + 1));
  }
  testing::expect_input_error(
      [&] { SiteDb db(file); },
      file.string() + ": its schema version " + std::to_string(SiteDb::kSchemaVersion + 1) +
          " is newer than this chatterlab's (" + std::to_string(SiteDb::kSchemaVersion) +
          "): run a newer chatterlab on this site, or give another --out");
  const auto text = dir.path() / "notes.sqlite";
  std::ofstream(text) << "these are not the pages of a database, but plain text of some length\n";
  testing::expect_input_error(
      [&] { SiteDb db(text); },
      text.string() + ": not a chatterlab site database (file is not a database)");
}

TEST(SiteDb, AnotherProgramsDatabaseIsRefusedAndLeftUntouched) {
  // Schema version 0 with tables in it: another program's SQLite file, even one with a table
  // named runs, is neither migrated nor changed.
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "mileage.sqlite";
  {
    SiteDb db(file);
    db.exec(
        "DROP TABLE trend_values; DROP TABLE test_cache; DROP TABLE campaign_runs; "
        "DROP TABLE runs; CREATE TABLE runs (car TEXT, km REAL); CREATE TABLE notes (x); "
        "INSERT INTO runs VALUES ('blue', 12.5); PRAGMA user_version = 0");
  }
  const std::string before = bytes_of(file);
  ASSERT_FALSE(before.empty());
  testing::expect_input_error([&] { SiteDb db(file); },
                              file.string() +
                                  ": not a chatterlab site database (its schema version is 0, yet "
                                  "it already holds tables: notes, runs)");
  EXPECT_EQ(bytes_of(file), before);
}

TEST(SiteDb, ARefusedFileIsClosed) {
  // The constructor throws after opening the file: its sqlite3 handle, and the file descriptor
  // it holds, must not outlive the exception.
  render::TempDir dir("sitedb");
  const auto newer = dir.path() / "newer.sqlite";
  const auto foreign = dir.path() / "foreign.sqlite";
  {
    SiteDb a(newer);
    a.exec("PRAGMA user_version = " + std::to_string(SiteDb::kSchemaVersion + 1));
    SiteDb b(foreign);
    b.exec("DROP TABLE trend_values; DROP TABLE test_cache; PRAGMA user_version = 0");
  }
  const std::size_t before = open_descriptors();
  for (const auto& file : {newer, foreign}) {
    EXPECT_THROW(SiteDb db(file), InputError) << file;
    EXPECT_EQ(open_descriptors(), before) << file;
  }
}

TEST(SiteDb, TwoProcessesOpeningANewFileMigrateItOnce) {
  // The child turns the file back into a new one (schema version 0, no tables), takes the write
  // lock and migrates it only after the parent has read version 0 and waits for that lock; the
  // parent then finds the schema in place instead of creating its tables a second time.
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  { SiteDb db(file); }
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(ready[0]);
    try {
      SiteDb db(file);
      db.exec(
          "DROP TABLE trend_values; DROP TABLE test_cache; DROP TABLE campaign_runs; "
          "DROP TABLE runs; PRAGMA user_version = 0");
      db.exec("BEGIN IMMEDIATE");
      const char c = 'x';
      if (::write(ready[1], &c, 1) != 1) ::_exit(2);
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      for (const auto& m : SiteDb::migrations()) db.exec(m);
      db.exec("PRAGMA user_version = " + std::to_string(SiteDb::kSchemaVersion));
      db.exec("COMMIT");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "child: %s\n", e.what());
      ::_exit(3);
    }
    ::_exit(0);
  }
  ::close(ready[1]);
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  ::close(ready[0]);
  {
    SiteDb db(file);  // reads version 0, then waits for the child's write lock
    EXPECT_EQ(db.schema_version(), SiteDb::kSchemaVersion);
    EXPECT_EQ(count(db, "runs"), 0);
  }
  EXPECT_EQ(exit_status(child), 0);
}

TEST(SiteDb, SeveralProcessesOpeningANewFileAtOnceAllSucceed) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  int go[2];
  ASSERT_EQ(::pipe(go), 0);
  std::vector<pid_t> children;
  for (int i = 0; i < 6; ++i) {
    children.push_back(child_running(go, [&] {
      SiteDb db(file);
      add_run(db, "child");
    }));
  }
  ::close(go[0]);
  ::close(go[1]);  // all start now
  for (const pid_t child : children) EXPECT_EQ(exit_status(child), 0);
  SiteDb db(file);
  EXPECT_EQ(db.schema_version(), SiteDb::kSchemaVersion);
  EXPECT_EQ(count(db, "runs"), 6);
}

TEST(SiteDb, AFailingStatementNamesItsSql) {
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  SiteDb db(file);
  EXPECT_EQ(runtime_error_of([&] {
              SiteDb::Statement s(db, "INSERT INTO runs (id) VALUES (1)");
              s.step();
            }),
            file.string() +
                ": statement failed (INSERT INTO runs (id) VALUES (1)): NOT NULL constraint "
                "failed: runs.started_utc");
  EXPECT_EQ(runtime_error_of([&] { SiteDb::Statement s(db, "SELECT x FROM nowhere"); }),
            file.string() + ": cannot prepare (SELECT x FROM nowhere): no such table: nowhere");
  // exec() names the statement of its SQL that failed, on one line.
  EXPECT_EQ(runtime_error_of([&] {
              db.exec(
                  "CREATE TABLE scratch (x NOT NULL);\n"
                  "INSERT INTO scratch VALUES (1);\n"
                  "INSERT INTO scratch\n  VALUES (NULL);");
            }),
            file.string() +
                ": statement failed (INSERT INTO scratch VALUES (NULL)): NOT NULL constraint "
                "failed: scratch.x");
  // Long SQL is cut after 120 characters.
  const std::string columns(200, 'c');
  EXPECT_EQ(runtime_error_of([&] { SiteDb::Statement s(db, "SELECT " + columns); }),
            file.string() + ": cannot prepare (SELECT " + columns.substr(0, 113) +
                "...): no such column: " + columns);
}

TEST(SiteDb, ATransactionLeftWithoutCommitIsRolledBack) {
  // A reopened file is not migrated again; a transaction left without commit (an exception
  // inside it) leaves nothing of what it did.
  render::TempDir dir("sitedb");
  const auto file = dir.path() / "history.sqlite";
  { SiteDb db(file); }
  SiteDb db(file);
  EXPECT_EQ(db.schema_version(), SiteDb::kSchemaVersion);
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
