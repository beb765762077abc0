#include "results/sqlite_connection.hpp"

#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/statvfs.h>

#include <cctype>

namespace armfarm {

// ---- SqliteConnection ----

namespace {

// A file: URI of `path` (RFC 3986: every byte but unreserved ones and '/' percent-encoded, so a
// '?', '#' or '%' in a name stays part of the name).
std::string make_file_uri(const std::string& path, const char* query) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string uri = "file:";
  for (std::size_t i = 0; i < path.size(); ++i) {
    const char c = path[i];
    const unsigned char byte = static_cast<unsigned char>(c);
    // A second leading '/' is encoded too: "file://" would start an authority.
    if (std::isalnum(byte) || (c == '/' && i != 1) || c == '-' || c == '.' || c == '_' || c == '~') {
      uri += c;
    } else {
      uri += '%';
      uri += kHex[byte >> 4];
      uri += kHex[byte & 15];
    }
  }
  return uri + "?" + query;
}

// True when `path` lies on a filesystem mounted read-only: nothing can write the file there.
// A file there with a -wal beside it is not opened immutable: that would ignore the WAL's
// commits (SQLite then reads it through the existing -shm, or refuses it).
bool is_immutable_file(const std::string& path) {
  struct statvfs info {};
  if (::statvfs(path.c_str(), &info) != 0 || (info.f_flag & ST_RDONLY) == 0) return false;
  struct stat wal {};
  return ::stat((path + "-wal").c_str(), &wal) != 0 || wal.st_size == 0;
}

}  // namespace

SqliteConnection::SqliteConnection(const std::string& path, bool read_only) : path_(path) {
  // Reading a WAL file needs its -shm index, which a read-only filesystem cannot hold: there
  // the file is opened immutable (no locks, no -shm), which is sound because nothing can
  // change it. Elsewhere mode=ro: a reader that sees writers' commits.
  const std::string name =
      !read_only ? path : make_file_uri(path, is_immutable_file(path) ? "immutable=1" : "mode=ro");
  const int flags = read_only ? (SQLITE_OPEN_READONLY | SQLITE_OPEN_URI) : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  const int rc = sqlite3_open_v2(name.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ != nullptr ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw StoreError(path + ": cannot open the database: " + message);
  }
  sqlite3_extended_result_codes(db_, 1);
  // Readers wait for a writer's lock as well (WAL checkpoints, schema changes).
  sqlite3_busy_timeout(db_, 10000);
}

SqliteConnection::SqliteConnection(const std::string& path, const std::string& uri) : path_(path) {
  const int rc = sqlite3_open_v2(uri.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ != nullptr ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw StoreError(path + ": cannot open a copy of the database: " + message);
  }
  sqlite3_extended_result_codes(db_, 1);
}

namespace {
void copy_database(sqlite3* from, sqlite3* to, const std::string& path) {
  sqlite3_backup* backup = sqlite3_backup_init(to, "main", from, "main");
  if (backup == nullptr) throw StoreError(path + ": cannot copy the database: " + sqlite3_errmsg(to));
  const int rc = sqlite3_backup_step(backup, -1);
  sqlite3_backup_finish(backup);
  if (rc != SQLITE_DONE) throw StoreError(path + ": cannot copy the database: " + sqlite3_errstr(rc));
}
}  // namespace

void SqliteConnection::copy_to_file(const std::string& target) {
  SqliteConnection copy(target, target);
  copy_database(db_, copy.db_, path_);
}

std::unique_ptr<SqliteConnection> SqliteConnection::make_memory_copy(const std::string& path) {
  SqliteConnection source(path, true);
  auto copy = std::make_unique<SqliteConnection>(path, std::string(":memory:"));
  copy_database(source.db_, copy->db_, path);
  return copy;
}

SqliteConnection::~SqliteConnection() { sqlite3_close_v2(db_); }

void SqliteConnection::fail(const std::string& what) const {
  throw StoreError(path_, what + ": " + sqlite3_errmsg(db_), sqlite3_extended_errcode(db_));
}

void SqliteConnection::execute(const std::string& sql) {
  char* error = nullptr;
  const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    const std::string message = error != nullptr ? error : "unknown error";
    sqlite3_free(error);
    throw StoreError(path_, message, rc);
  }
}

std::int64_t SqliteConnection::query_int(const std::string& sql) {
  SqliteStatement statement(*this, sql);
  if (!statement.step()) throw StoreError(path_, "no result for " + sql);
  return statement.column_int(0);
}

std::int64_t SqliteConnection::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

int SqliteConnection::changes() const { return sqlite3_changes(db_); }

// ---- SqliteStatement ----

SqliteStatement::SqliteStatement(SqliteConnection& connection, const std::string& sql) : connection_(&connection) {
  if (sqlite3_prepare_v2(connection.handle(), sql.c_str(), static_cast<int>(sql.size() + 1), &statement_, nullptr) !=
      SQLITE_OK) {
    connection.fail("cannot prepare \"" + sql.substr(0, 60) + "\"");
  }
}

SqliteStatement::SqliteStatement(SqliteStatement&& other) noexcept
    : connection_(other.connection_), statement_(other.statement_) {
  other.statement_ = nullptr;
}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(statement_); }

SqliteStatement& SqliteStatement::bind(int index, std::int64_t value) {
  if (sqlite3_bind_int64(statement_, index, value) != SQLITE_OK) connection_->fail("bind");
  return *this;
}

SqliteStatement& SqliteStatement::bind(int index, double value) {
  if (sqlite3_bind_double(statement_, index, value) != SQLITE_OK) connection_->fail("bind");
  return *this;
}

SqliteStatement& SqliteStatement::bind(int index, const std::string& value) {
  if (sqlite3_bind_text(statement_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT) !=
      SQLITE_OK) {
    connection_->fail("bind");
  }
  return *this;
}

SqliteStatement& SqliteStatement::bind(int index, const std::vector<unsigned char>& blob) {
  if (sqlite3_bind_blob64(statement_, index, blob.data(), blob.size(), SQLITE_TRANSIENT) != SQLITE_OK) {
    connection_->fail("bind");
  }
  return *this;
}

SqliteStatement& SqliteStatement::bind_null(int index) {
  if (sqlite3_bind_null(statement_, index) != SQLITE_OK) connection_->fail("bind");
  return *this;
}

bool SqliteStatement::step() {
  const int rc = sqlite3_step(statement_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  connection_->fail("query failed");
}

void SqliteStatement::execute() {
  while (step()) {
  }
  reset();
}

void SqliteStatement::reset() {
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

bool SqliteStatement::is_null(int column) const { return sqlite3_column_type(statement_, column) == SQLITE_NULL; }

namespace {

const char* storage_class_name(int type) {
  switch (type) {
    case SQLITE_INTEGER: return "an integer";
    case SQLITE_FLOAT: return "a real";
    case SQLITE_TEXT: return "text";
    case SQLITE_BLOB: return "a blob";
    default: return "NULL";
  }
}

}  // namespace

// A value of the wrong storage class is damage (armfarm never writes one): refused, not coerced
// (SQLite would read 'abc' as 0).
void SqliteStatement::require_type(int column, bool allowed, const char* wanted) const {
  if (allowed) return;
  const char* name = sqlite3_column_name(statement_, column);
  throw StoreError(connection_->path(), std::string("damaged armfarm database: column ") + (name ? name : "?") + " holds " +
                                            storage_class_name(sqlite3_column_type(statement_, column)) + " where " + wanted + " belongs");
}

std::int64_t SqliteStatement::column_int(int column) const {
  require_type(column, sqlite3_column_type(statement_, column) == SQLITE_INTEGER, "an integer");
  return sqlite3_column_int64(statement_, column);
}

double SqliteStatement::column_double(int column) const {
  const int type = sqlite3_column_type(statement_, column);
  require_type(column, type == SQLITE_FLOAT || type == SQLITE_INTEGER, "a number");
  return sqlite3_column_double(statement_, column);
}

std::string SqliteStatement::column_text(int column) const {
  const int type = sqlite3_column_type(statement_, column);
  require_type(column, type == SQLITE_TEXT || type == SQLITE_NULL, "text");
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement_, column));
  if (text == nullptr) return {};
  return std::string(text, static_cast<std::size_t>(sqlite3_column_bytes(statement_, column)));
}

std::optional<std::string> SqliteStatement::column_optional_text(int column) const {
  if (is_null(column)) return std::nullopt;
  return column_text(column);
}

std::optional<double> SqliteStatement::column_optional_double(int column) const {
  if (is_null(column)) return std::nullopt;
  return column_double(column);
}

std::vector<unsigned char> SqliteStatement::column_blob(int column) const {
  const int type = sqlite3_column_type(statement_, column);
  require_type(column, type == SQLITE_BLOB || type == SQLITE_NULL, "a blob");
  const auto* data = static_cast<const unsigned char*>(sqlite3_column_blob(statement_, column));
  const int size = sqlite3_column_bytes(statement_, column);
  if (data == nullptr || size <= 0) return {};
  return std::vector<unsigned char>(data, data + size);
}

// ---- SqliteTransaction ----

SqliteTransaction::SqliteTransaction(SqliteConnection& connection) : connection_(connection) {
  connection_.execute("BEGIN IMMEDIATE");
}

SqliteTransaction::~SqliteTransaction() {
  if (!open_) return;
  try {
    connection_.execute("ROLLBACK");
  } catch (const StoreError&) {
    // Nothing more can be done: the connection's own rollback happens on close.
  }
}

void SqliteTransaction::commit() {
  connection_.execute("COMMIT");
  open_ = false;
}

}  // namespace armfarm
