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
)sql",
      // Version 2: the per-test cache keeps each node's kind result (zlib-compressed bytes,
      // app/nightly/test_cache.h); NULL where none is kept. Groups have rows too.
      R"sql(
ALTER TABLE test_cache ADD COLUMN result BLOB;
)sql"};
  return m;
}

SiteDb::SiteDb(const std::filesystem::path& file) : file_(file) {
  sqlite3* handle = nullptr;
  const int opened =
      sqlite3_open_v2(file.c_str(), &handle, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  db_.reset(handle);  // closed from here on, also when this constructor throws
  if (opened != SQLITE_OK) {
    throw InputError(file.string() + ": cannot be opened as a database: " +
                     (handle ? sqlite3_errmsg(handle) : "out of memory"));
  }
  sqlite3_busy_timeout(db_.get(), 10000);
  int version = 0;
  try {
    exec("PRAGMA foreign_keys = ON");
    version = schema_version();
  } catch (const std::exception&) {  // SQLite cannot read it: "file is not a database"
    throw InputError(file.string() + ": not a chatterlab site database (" +
                     sqlite3_errmsg(db_.get()) + ")");
  }
  const auto refuse_newer = [&](int v) {
    if (v <= kSchemaVersion) return;
    throw InputError(file.string() + ": its schema version " + std::to_string(v) +
                     " is newer than this chatterlab's (" + std::to_string(kSchemaVersion) +
                     "): run a newer chatterlab on this site, or give another --out");
  };
  refuse_newer(version);
  if (version == kSchemaVersion) return;
  // Another process (a second nightly, compare --site) may have migrated the file since the read
  // above: read the version again under the write lock and migrate only what is still missing.
  Transaction t(*this);
  version = schema_version();
  refuse_newer(version);
  if (version == 0) {
    // Version 0 is a file no chatterlab has written: it must hold no tables yet. One that does
    // belongs to another program, and is left untouched.
    Statement count(*this, "SELECT COUNT(*) FROM sqlite_master");
    if (count.step() && count.integer(0) > 0) {
      std::string tables;
      Statement names(
          *this, "SELECT name FROM sqlite_master WHERE type IN ('table', 'view') ORDER BY name");
      for (int n = 0; names.step(); ++n) {  // the first five names
        if (n < 5) tables += (n > 0 ? ", " : "") + names.text(0);
        if (n == 5) tables += ", ...";
      }
      throw InputError(file.string() +
                       ": not a chatterlab site database (its schema version is 0, yet it "
                       "already holds tables: " +
                       tables + ")");
    }
  }
  if (version < kSchemaVersion) {  // else: migrated by the other process meanwhile
    for (int v = version; v < kSchemaVersion; ++v) exec(migrations()[static_cast<size_t>(v)]);
    exec("PRAGMA user_version = " + std::to_string(kSchemaVersion));
  }
  t.commit();
}

SiteDb::~SiteDb() = default;

void SiteDb::Close::operator()(sqlite3* db) const { sqlite3_close_v2(db); }

namespace {

// The SQL of a statement for a message: on one line, without its closing ';', the first 120
// characters.
std::string sql_for_message(const std::string& sql) {
  std::string out;
  for (const char c : sql) {
    const bool space = c == ' ' || c == '\n' || c == '\t' || c == '\r';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out.size() > 120 ? out.substr(0, 120) + "..." : out;
}

}  // namespace

void SiteDb::fail(const std::string& what, const std::string& sql) {
  throw std::runtime_error(file_.string() + ": " + what + " (" + sql_for_message(sql) +
                           "): " + sqlite3_errmsg(db_.get()));
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
  // Statement by statement, as sqlite3_exec does, so that a failure names its own statement.
  const char* next = sql.c_str();
  while (*next != '\0') {
    const char* start = next;
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_.get(), start, -1, &raw, &next) != SQLITE_OK) {
      sqlite3_finalize(raw);
      fail("cannot prepare", start);
    }
    if (!raw) continue;  // only white space or a comment was left
    const std::string one(start, static_cast<std::size_t>(next - start));
    int rc = SQLITE_ROW;
    while (rc == SQLITE_ROW) rc = sqlite3_step(raw);
    if (rc != SQLITE_DONE) {
      const std::string why = sqlite3_errmsg(db_.get());
      sqlite3_finalize(raw);
      throw std::runtime_error(file_.string() + ": statement failed (" + sql_for_message(one) +
                               "): " + why);
    }
    sqlite3_finalize(raw);
  }
}

std::int64_t SiteDb::last_insert_id() { return sqlite3_last_insert_rowid(db_.get()); }

SiteDb::Statement::Statement(SiteDb& db, const std::string& sql) : db_(db), sql_(sql) {
  if (sqlite3_prepare_v2(db.db_.get(), sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
    sqlite3_finalize(stmt_);
    db.fail("cannot prepare", sql_);
  }
}

SiteDb::Statement::~Statement() { sqlite3_finalize(stmt_); }

void SiteDb::Statement::bind_failed(int i) {
  db_.fail("cannot bind parameter " + std::to_string(i) + " of", sql_);
}

SiteDb::Statement& SiteDb::Statement::bind(int i, const std::string& text) {
  if (sqlite3_bind_text(stmt_, i, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT) !=
      SQLITE_OK) {
    bind_failed(i);
  }
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind(int i, double v) {
  if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) bind_failed(i);
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind(int i, std::int64_t v) {
  if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) bind_failed(i);
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind_blob(int i, const std::string& bytes) {
  if (sqlite3_bind_blob64(stmt_, i, bytes.data(), bytes.size(), SQLITE_TRANSIENT) != SQLITE_OK) {
    bind_failed(i);
  }
  return *this;
}

SiteDb::Statement& SiteDb::Statement::bind_null(int i) {
  if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) bind_failed(i);
  return *this;
}

bool SiteDb::Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  db_.fail("statement failed", sql_);
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
