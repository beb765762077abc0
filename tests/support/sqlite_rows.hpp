// Reading a results database the way a user's script does (plain sqlite3, no store class), for
// tests that check what a run or a migration left in the file. Link SQLite (PkgConfig::SQLITE3).
#pragma once

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

}  // namespace armfarm::test_support
