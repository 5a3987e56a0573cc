// The nightly site's database (docs/nightly.md#the-database): an embedded SQLite file,
// <site>/history.sqlite, holding the test cache and the run history. Its schema carries a
// version (SQLite's user_version); opening a file of an older version migrates it in one
// transaction, a newer one is refused, and so is a foreign SQLite file (schema version 0 but
// tables already in it). Every write the nightly run makes is inside a transaction, so a run
// killed at any moment leaves the previous state readable.
//
// SiteLock keeps two runs off one site: the second waits or is refused with a message naming
// the run that holds it. The lock is an flock(2) on <site>/.nightly.lock, released by the
// kernel when its holder exits for any reason (a killed run leaves no stale lock).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
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
  static constexpr int kSchemaVersion = 2;

  // Opens or creates the database and migrates it to kSchemaVersion. The version is read again
  // inside the migration's write transaction, so two processes opening a new file at once
  // migrate it once: the second waits for the first and finds the schema in place.
  // @throws InputError naming the file: not a database, not a chatterlab site database
  //         (schema version 0 but tables already in it), or a newer schema than this program's
  explicit SiteDb(const std::filesystem::path& file);
  ~SiteDb();
  SiteDb(const SiteDb&) = delete;
  SiteDb& operator=(const SiteDb&) = delete;

  int schema_version();
  // SQLite's PRAGMA integrity_check: "ok", or the problems it found.
  std::string integrity_check();
  // Runs SQL without results, one statement after the other.
  // @throws std::runtime_error naming the statement that failed and SQLite's message
  void exec(const std::string& sql);

  // A prepared statement: bind from 1, step() until it returns false, read columns from 0.
  // Its failures throw std::runtime_error naming the file, the statement's SQL and SQLite's
  // message.
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
    [[noreturn]] void bind_failed(int i);
    SiteDb& db_;
    std::string sql_;  // for messages
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
  // Throws std::runtime_error "<file>: <what> (<sql>): <SQLite's message>".
  [[noreturn]] void fail(const std::string& what, const std::string& sql);
  // Closes the connection with sqlite3_close_v2, also when the constructor throws.
  struct Close {
    void operator()(sqlite3* db) const;
  };
  std::filesystem::path file_;
  std::unique_ptr<sqlite3, Close> db_;
};

}  // namespace chatterlab::app
