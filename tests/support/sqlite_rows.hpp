// Reading a results database the way a user's script does (plain sqlite3, no store class), for
// tests that check what a run or a migration left in the file. Link SQLite (PkgConfig::SQLITE3).
#pragma once

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>
#include <vector>

namespace armfarm::test_support {

/// Every row `sql` returns on the database file `db` (several statements allowed, so a test may
/// also change the file), each row's columns joined by "|", NULL as "NULL". Opens the file
/// read-write without creating it (empty result when it does not exist) and waits up to 2 s
/// for a lock another process holds.
inline std::vector<std::string> query_rows(const std::string& db, const std::string& sql) {
  std::vector<std::string> rows;
  sqlite3* handle = nullptr;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close(handle);
    return rows;
  }
  sqlite3_busy_timeout(handle, 2000);
  sqlite3_exec(
      handle, sql.c_str(),
      [](void* out, int n, char** values, char**) {
        std::string row;
        for (int i = 0; i < n; ++i) row += (i ? "|" : "") + std::string(values[i] ? values[i] : "NULL");
        static_cast<std::vector<std::string>*>(out)->push_back(row);
        return 0;
      },
      &rows, nullptr);
  sqlite3_close(handle);
  return rows;
}

/// Every row `sql` (one statement) returns on the existing database file `db_path`, opened
/// read-only as a user's reader would; each row's columns joined by "|", NULL as "NULL". Fails
/// the test when the file cannot be opened or the statement cannot be prepared.
inline std::vector<std::string> query_rows_read_only(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  std::vector<std::string> rows;
  while (statement && sqlite3_step(statement) == SQLITE_ROW) {
    std::string row;
    for (int c = 0; c < sqlite3_column_count(statement); ++c) {
      const auto* text = sqlite3_column_text(statement, c);
      row += (c ? "|" : "") + std::string(text ? reinterpret_cast<const char*>(text) : "NULL");
    }
    rows.push_back(row);
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return rows;
}

}  // namespace armfarm::test_support
