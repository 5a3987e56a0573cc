#include "app/nightly/site_db.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "analysis/common/summary.h"

namespace chatterlab::app {

namespace {

std::string lock_holder(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

}  // namespace

SiteLock::SiteLock(const std::filesystem::path& site, bool wait) {
  std::error_code ec;
  std::filesystem::create_directories(site, ec);
  const auto file = site / ".nightly.lock";
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw InputError(file.string() + ": cannot be opened: " + std::strerror(errno));
  }
  if (::flock(fd_, LOCK_EX | (wait ? 0 : LOCK_NB)) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) {
      const std::string holder = lock_holder(file);
      throw InputError("the site " + site.string() + " is in use by another chatterlab nightly (" +
                       (holder.empty() ? std::string("starting") : holder) +
                       "): wait for it to end, or give --wait to queue behind it");
    }
    throw InputError(file.string() + ": cannot be locked: " + std::strerror(err));
  }
  // Who holds it, for the message of a run refused meanwhile.
  std::ostringstream who;
  who << "process " << ::getpid() << ", started " << std::time(nullptr) << " s after the epoch";
  const std::string text = who.str() + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    const ssize_t written = ::pwrite(fd_, text.data(), text.size(), 0);
    (void)written;  // the holder's description is informative only
  }
}

SiteLock::~SiteLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the flock
}

const std::vector<std::string>& SiteDb::migrations() {
  // Version 1: the run history, each campaign's state per run, the test cache and the values
  // the trend pages plot (docs/nightly.md#the-database).
  static const std::vector<std::string> m = {
      R"sql(
CREATE TABLE runs (
  id INTEGER PRIMARY KEY,
  started_utc TEXT NOT NULL,
  finished_utc TEXT NOT NULL,
  version TEXT NOT NULL,
  options TEXT NOT NULL,
  runtime_s REAL NOT NULL,
  status TEXT NOT NULL
);
CREATE TABLE campaign_runs (
  run_id INTEGER NOT NULL REFERENCES runs(id),
  name TEXT NOT NULL,
  path TEXT NOT NULL,
  status TEXT NOT NULL,
  message TEXT NOT NULL,
  last_change_utc TEXT NOT NULL,
  recomputed TEXT NOT NULL,
  cached TEXT NOT NULL,
  flags TEXT NOT NULL,
  campaign_key TEXT NOT NULL,
  results_sha256 TEXT NOT NULL,
  results BLOB,
  PRIMARY KEY (run_id, name)
);
CREATE TABLE test_cache (
  campaign TEXT NOT NULL,
  test TEXT NOT NULL,
  key_sha256 TEXT NOT NULL,
  payload BLOB NOT NULL,
  run_id INTEGER NOT NULL,
  PRIMARY KEY (campaign, test)
);
CREATE TABLE trend_values (
  run_id INTEGER NOT NULL REFERENCES runs(id),
  campaign TEXT NOT NULL,
  key TEXT NOT NULL,
  value REAL,
  lo REAL,
  hi REAL,
  PRIMARY KEY (run_id, campaign, key)
);
)sql"};
  return m;
}

SiteDb::SiteDb(const std::filesystem::path& file) : file_(file) {
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(file.string() + ": cannot be opened as a database: " + why);
  }
  sqlite3_busy_timeout(db_, 10000);
  int version = 0;
  try {
    exec("PRAGMA foreign_keys = ON");
    version = schema_version();
  } catch (const std::exception& e) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(file.string() + ": not a chatterlab site database: " + e.what());
  }
  if (version > kSchemaVersion) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(file.string() + ": its schema version " + std::to_string(version) +
                     " is newer than this chatterlab's (" + std::to_string(kSchemaVersion) +
                     "): run a newer chatterlab on this site, or give another --out");
  }
  if (version < kSchemaVersion) {
    Transaction t(*this);
    for (int v = version; v < kSchemaVersion; ++v) exec(migrations()[static_cast<size_t>(v)]);
    exec("PRAGMA user_version = " + std::to_string(kSchemaVersion));
    t.commit();
  }
}

SiteDb::~SiteDb() {
  if (db_) sqlite3_close_v2(db_);
}

void SiteDb::fail(const std::string& what) {
  throw std::runtime_error(file_.string() + ": " + what + ": " + sqlite3_errmsg(db_));
}

int SiteDb::schema_version() {
  Statement s(*this, "PRAGMA user_version");
  return s.step() ? static_cast<int>(s.integer(0)) : 0;
}

std::string SiteDb::integrity_check() {
  Statement s(*this, "PRAGMA integrity_check");
  std::string out;
  while (s.step()) out += (out.empty() ? "" : "\n") + s.text(0);
  return out;
}

void SiteDb::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "unknown error";
    sqlite3_free(err);
    throw std::runtime_error(file_.string() + ": " + why);
  }
}

std::int64_t SiteDb::last_insert_id() { return sqlite3_last_insert_rowid(db_); }

SiteDb::Statement::Statement(SiteDb& db, const std::string& sql) : db_(db) {
  if (sqlite3_prepare_v2(db.db_, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
    db.fail("cannot prepare '" + sql + "'");
  }
}

SiteDb::Statement::~Statement() { sqlite3_finalize(stmt_); }

SiteDb::Statement& SiteDb::Statement::bind(int i, const std::string& text) {
  if (sqlite3_bind_text(stmt_, i, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT) !=
      SQLITE_OK) {
    db_.fail("cannot bind");
  }
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind(int i, double v) {
  if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) db_.fail("cannot bind");
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind(int i, std::int64_t v) {
  if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) db_.fail("cannot bind");
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind_blob(int i, const std::string& bytes) {
  if (sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_TRANSIENT) != SQLITE_OK) {
    db_.fail("cannot bind");
  }
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind_null(int i) {
  if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) db_.fail("cannot bind");
  return *this;
}

bool SiteDb::Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  db_.fail("statement failed");
}

void SiteDb::Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::string SiteDb::Statement::text(int col) const {
  const auto* p = sqlite3_column_text(stmt_, col);
  return p ? std::string(reinterpret_cast<const char*>(p),
                         static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
           : std::string();
}

double SiteDb::Statement::real(int col) const { return sqlite3_column_double(stmt_, col); }

std::int64_t SiteDb::Statement::integer(int col) const { return sqlite3_column_int64(stmt_, col); }

bool SiteDb::Statement::is_null(int col) const {
  return sqlite3_column_type(stmt_, col) == SQLITE_NULL;
}

std::string SiteDb::Statement::blob(int col) const {
  const void* p = sqlite3_column_blob(stmt_, col);
  const int n = sqlite3_column_bytes(stmt_, col);
  return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(n)) : std::string();
}

SiteDb::Transaction::Transaction(SiteDb& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

SiteDb::Transaction::~Transaction() {
  if (!open_) return;
  try {
    db_.exec("ROLLBACK");
  } catch (...) {  // a destructor does not throw; SQLite rolls back on close anyway
  }
}

void SiteDb::Transaction::commit() {
  db_.exec("COMMIT");
  open_ = false;
}

}  // namespace chatterlab::app
