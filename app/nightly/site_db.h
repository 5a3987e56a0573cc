// The nightly site's database (docs/nightly.md#the-database): an embedded SQLite file,
// <site>/history.sqlite, holding the test cache and the run history. Its schema carries a
// version (SQLite's user_version); opening a file of an older version migrates it in one
// transaction, a newer one is refused. Every write the nightly run makes is inside a
// transaction, so a run killed at any moment leaves the previous state readable.
//
// SiteLock keeps two runs off one site: the second waits or is refused with a message naming
// the run that holds it. The lock is an flock(2) on <site>/.nightly.lock, released by the
// kernel when its holder exits for any reason (a killed run leaves no stale lock).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace chatterlab::app {

class SiteLock {
 public:
  // Takes the site's lock; wait = false: a held lock throws InputError naming the site and
  // the holder's process id and start time. Creates the site folder when missing.
  SiteLock(const std::filesystem::path& site, bool wait);
  ~SiteLock();
  SiteLock(const SiteLock&) = delete;
  SiteLock& operator=(const SiteLock&) = delete;

 private:
  int fd_ = -1;
};

class SiteDb {
 public:
  // The schema this program writes; migrations() holds one step per version.
  static constexpr int kSchemaVersion = 1;

  // Opens or creates the database and migrates it to kSchemaVersion.
  // @throws InputError naming the file: not a database, or a newer schema than this program's
  explicit SiteDb(const std::filesystem::path& file);
  ~SiteDb();
  SiteDb(const SiteDb&) = delete;
  SiteDb& operator=(const SiteDb&) = delete;

  int schema_version();
  // SQLite's PRAGMA integrity_check: "ok", or the problems it found.
  std::string integrity_check();
  // Runs SQL without results. @throws std::runtime_error with SQLite's message
  void exec(const std::string& sql);

  // A prepared statement: bind from 1, step() until it returns false, read columns from 0.
  class Statement {
   public:
    Statement(SiteDb& db, const std::string& sql);
    ~Statement();
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;
    Statement& bind(int i, const std::string& text);
    Statement& bind(int i, double v);
    Statement& bind(int i, std::int64_t v);
    Statement& bind_blob(int i, const std::string& bytes);
    Statement& bind_null(int i);
    bool step();  // true: a row is ready
    void reset();
    std::string text(int col) const;
    double real(int col) const;
    std::int64_t integer(int col) const;
    bool is_null(int col) const;
    std::string blob(int col) const;

   private:
    SiteDb& db_;
    sqlite3_stmt* stmt_ = nullptr;
  };

  // BEGIN IMMEDIATE on construction; ROLLBACK on destruction unless commit() was called.
  class Transaction {
   public:
    explicit Transaction(SiteDb& db);
    ~Transaction();
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void commit();

   private:
    SiteDb& db_;
    bool open_ = true;
  };

  std::int64_t last_insert_id();
  const std::filesystem::path& file() const { return file_; }

  // The SQL of each migration step: element v-1 takes a database from version v-1 to v.
  static const std::vector<std::string>& migrations();

 private:
  [[noreturn]] void fail(const std::string& what);
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

}  // namespace chatterlab::app
