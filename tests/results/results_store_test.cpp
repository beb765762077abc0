// The results store's handle: clear errors for files that are not (or not yet) armfarm
// databases. Writes, reads, the per-sweep views and merges: store_writes_test.cpp,
// store_reads_test.cpp, sweep_views_test.cpp and store_merge_test.cpp.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/results_store_fixture.hpp"
#include "support/sqlite_rows.hpp"
#include <sqlite3.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

using test_support::make_jobs;
using test_support::make_sweep;
using test_support::ResultsStoreTest;

TEST_F(ResultsStoreTest, FilesThatAreNotArmfarmDatabasesGiveOneLineErrors) {
  auto expect_error = [&](const std::string& file, ResultsStore::Mode mode, const std::string& fragment) {
    try {
      ResultsStore::open(file, mode);
      ADD_FAILURE() << file << " opened";
    } catch (const StoreError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file), std::string::npos) << what;
      EXPECT_NE(what.find(fragment), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  };
  expect_error(path("missing.db"), ResultsStore::Mode::read_only, "no such");

  std::ofstream(path("text.db")) << "this is not a database, just some text that is long enough to matter\n"
                                 << std::string(2000, 'x');
  expect_error(path("text.db"), ResultsStore::Mode::read_write, "not a readable SQLite database");
  expect_error(path("text.db"), ResultsStore::Mode::read_only, "not a readable SQLite database");

  // A database written by a newer armfarm.
  { ResultsStore::open(path("new.db"), ResultsStore::Mode::read_write); }
  test_support::query_rows_read_only(path("new.db"), "SELECT 1");
  {
    sqlite3* db = nullptr;
    sqlite3_open(path("new.db").c_str(), &db);
    sqlite3_exec(db, "PRAGMA user_version = 99", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  expect_error(path("new.db"), ResultsStore::Mode::read_write, "newer armfarm");

  // Another application's SQLite file.
  {
    sqlite3* db = nullptr;
    sqlite3_open(path("other.db").c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE t (x)", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  expect_error(path("other.db"), ResultsStore::Mode::read_write, "not an armfarm results database");

  // A real database with its header overwritten.
  {
    ResultsStore store = ResultsStore::open(path("corrupt.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(make_sweep("s"), make_jobs(50));
  }
  {
    std::fstream file(path("corrupt.db"), std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(0);
    file << "garbage garbage garbage garbage garbage garbage";
  }
  expect_error(path("corrupt.db"), ResultsStore::Mode::read_only, "not a readable SQLite database");
}

}  // namespace
}  // namespace armfarm
