// The `models` table: a job's stored model round-trips bit for bit, is replaced when the job runs
// again, is what a plain SQL reader sees, and merges with its job (a differing model is a conflict).
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include "support/test_database.hpp"
#include <sqlite3.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class ModelStoreTest : public test_support::ScratchFolderTest {
 protected:
  ModelStoreTest() : ScratchFolderTest("models_store") {}
};

JobResultRecord make_result(const std::string& key, const std::string& bytes) {
  JobResultRecord result;
  result.key = key;
  result.status = "done";
  result.started_at = result.finished_at = make_utc_timestamp();
  // A stand-in hash of the stored form (the runner computes the real XXH3-128).
  char digits[40];
  std::snprintf(digits, sizeof digits, "%032zx", std::hash<std::string>{}(bytes));
  result.model = StoredModelRecord{"lwpr", std::string("xxh3-128:") + digits, bytes};
  return result;
}

// Every byte value, NUL included, as a model file may hold.
std::string make_bytes(int n, int salt) {
  std::string bytes;
  for (int i = 0; i < n; ++i) bytes.push_back(static_cast<char>((i * 37 + salt) & 0xff));
  return bytes;
}

TEST_F(ModelStoreTest, StoredModelsRoundTripAreReplacedAndReadableWithPlainSql) {
  const std::string bytes = make_bytes(5000, 0);
  {
    ResultsStore store = ResultsStore::open(path("m.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("s"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}, {"k2", {{"a", 2}}, {{"a", 2}}, 0}});
    JobResultRecord without = make_result("k2", "x");
    without.model.reset();
    store.insert_job_batch({{}, {make_result("k1", make_bytes(10, 1)), without}, {}}, "s");
    store.insert_job_batch({{}, {make_result("k1", bytes)}, {}}, "s");  // the job ran again
  }
  const ResultsStore store = ResultsStore::open(path("m.db"), ResultsStore::Mode::read_only);
  const auto model = store.find_job_model(store.find_job("k1")->id);
  ASSERT_TRUE(model.has_value());
  EXPECT_EQ(model->data, bytes);
  EXPECT_EQ(model->kind, "lwpr");
  EXPECT_FALSE(store.find_job_model(store.find_job("k2")->id).has_value());
  const std::vector<StoredModelInfo> listed = store.find_sweep_models("s");
  ASSERT_EQ(listed.size(), 1u);
  EXPECT_EQ(listed[0].job_key, "k1");
  EXPECT_EQ(listed[0].bytes, 5000);

  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path("m.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT count(*), length(data), bytes FROM models", -1, &statement, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(statement), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(statement, 0), 1);
  EXPECT_EQ(sqlite3_column_int(statement, 1), 5000);
  EXPECT_EQ(sqlite3_column_int(statement, 2), 5000);
  sqlite3_finalize(statement);
  sqlite3_close(db);
  EXPECT_TRUE(store.check_contents(false, 10).empty());

  // A damaged row is a finding of the contents check.
  ASSERT_EQ(sqlite3_open(path("m.db").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE models SET hash = 'abc'", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  const std::vector<std::string> findings =
      ResultsStore::open(path("m.db"), ResultsStore::Mode::read_only).check_contents(false, 10);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_NE(findings[0].find("models of job row"), std::string::npos) << findings[0];
}

TEST_F(ModelStoreTest, MergeCopiesAJobsModelAndADifferentModelIsAConflict) {
  for (const char* name : {"a.db", "b.db"}) {
    ResultsStore store = ResultsStore::open(path(name), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("s"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    store.insert_job_batch({{}, {make_result("k1", make_bytes(100, name[0] == 'a' ? 0 : 1))}, {}}, "s");
  }
  ResultsStore out = ResultsStore::open(path("out.db"), ResultsStore::Mode::read_write);
  EXPECT_EQ(out.merge_from(path("a.db")).jobs_added, 1);
  EXPECT_EQ(out.find_job_model(out.find_job("k1")->id)->data, make_bytes(100, 0));
  const MergeReport again = out.merge_from(path("a.db"));
  EXPECT_EQ(again.jobs_identical, 1);
  EXPECT_TRUE(again.conflicts.empty());
  const MergeReport other = out.merge_from(path("b.db"));
  ASSERT_EQ(other.conflicts.size(), 1u);
  EXPECT_NE(other.conflicts[0].find("k1"), std::string::npos);
}

}  // namespace
}  // namespace armfarm
