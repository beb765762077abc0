#pragma once
// A thin RAII layer over the sqlite3 C API: a connection, prepared statements and transactions.
// Every failure throws StoreError with the database's file name and SQLite's message. Private to
// results/ (the rest of armfarm goes through ResultsStore).
#include "results/store_error.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace armfarm {

class SqliteConnection;

/// A prepared statement. Bind parameters are 1-based, columns 0-based.
class SqliteStatement {
 public:
  SqliteStatement(SqliteConnection& connection, const std::string& sql);
  SqliteStatement(SqliteStatement&&) noexcept;
  SqliteStatement& operator=(SqliteStatement&&) = delete;
  SqliteStatement(const SqliteStatement&) = delete;
  ~SqliteStatement();

  SqliteStatement& bind(int index, std::int64_t value);
  SqliteStatement& bind(int index, int value) { return bind(index, static_cast<std::int64_t>(value)); }
  SqliteStatement& bind(int index, double value);
  SqliteStatement& bind(int index, const std::string& value);
  SqliteStatement& bind(int index, const char* value) { return bind(index, std::string(value)); }
  SqliteStatement& bind(int index, const std::vector<unsigned char>& blob);
  SqliteStatement& bind_null(int index);
  template <typename T>
  SqliteStatement& bind(int index, const std::optional<T>& value) {
    return value ? bind(index, *value) : bind_null(index);
  }

  /// Advances; true while a row is available.
  bool step();
  /// Runs a statement that returns no rows (or ignores them), then resets it.
  void execute();
  /// Clears bindings and rewinds, ready to bind and step again.
  void reset();

  bool is_null(int column) const;
  /// Typed reads: a value of another storage class throws StoreError naming the file and column.
  std::int64_t column_int(int column) const;
  double column_double(int column) const;
  std::string column_text(int column) const;
  std::optional<std::string> column_optional_text(int column) const;
  std::optional<double> column_optional_double(int column) const;
  std::vector<unsigned char> column_blob(int column) const;

 private:
  void require_type(int column, bool allowed, const char* wanted) const;

  SqliteConnection* connection_;
  sqlite3_stmt* statement_ = nullptr;
};

class SqliteConnection {
 public:
  /// Opens `path` (read_only: must exist; otherwise created if absent).
  SqliteConnection(const std::string& path, bool read_only);
  /// Opens `uri` (e.g. ":memory:") under the name `path` used in messages.
  SqliteConnection(const std::string& path, const std::string& uri);
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;
  ~SqliteConnection();

  /// Runs one or more statements without results.
  void execute(const std::string& sql);
  SqliteStatement prepare(const std::string& sql) { return SqliteStatement(*this, sql); }
  /// The single integer a query returns (e.g. a PRAGMA).
  std::int64_t query_int(const std::string& sql);
  std::int64_t last_insert_rowid() const;
  int changes() const;

  const std::string& path() const { return path_; }
  sqlite3* handle() { return db_; }
  /// Copies the whole database into a new file `target` (SQLite's online backup).
  void copy_to_file(const std::string& target);
  /// A writable in-memory copy of the database file at `path` (which is only read); its
  /// path() is `path`, for messages.
  static std::unique_ptr<SqliteConnection> make_memory_copy(const std::string& path);
  /// A StoreError "<path>: <what>: <sqlite message>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

/// BEGIN IMMEDIATE on construction; ROLLBACK on destruction unless commit() was called.
class SqliteTransaction {
 public:
  explicit SqliteTransaction(SqliteConnection& connection);
  SqliteTransaction(const SqliteTransaction&) = delete;
  SqliteTransaction& operator=(const SqliteTransaction&) = delete;
  ~SqliteTransaction();
  void commit();

 private:
  SqliteConnection& connection_;
  bool open_ = true;
};

}  // namespace armfarm
