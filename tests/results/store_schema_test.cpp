// Schema version 2 (issue 11): NULL metrics with reasons, metric_info, timing-blind merges,
// collision-free sweep view names, and a version-1 file that still opens and migrates.
#include "results/results_store.hpp"
#include "results/sqlite_connection.hpp"
#include "results/store_error.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include "support/sqlite_rows.hpp"
#include "support/test_database.hpp"
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class ResultsStoreV2Test : public test_support::ScratchFolderTest {
 protected:
  ResultsStoreV2Test() : ScratchFolderTest("store_v2") {}
};

void execute_as_user(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  EXPECT_EQ(rc, SQLITE_OK) << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

SweepRegistration make_sweep(const std::string& name) {
  SweepRegistration sweep = testing::make_sweep_registration(name);
  sweep.metric_info = {{"tracking_nmse", "1", "joint error", "lower", "joint", "result"},
                       {"learner_us_per_update", "µs", "update time", "lower", "job", "timing"},
                       {"sim_seconds_per_wall_second", "s/s", "speed", "higher", "job", "timing"}};
  return sweep;
}

JobResultRecord make_result(const std::string& key, double nmse, double microseconds) {
  JobResultRecord result;
  result.key = key;
  result.status = "done";
  result.started_at = result.finished_at = make_utc_timestamp();
  result.metrics = {{0, "tracking_nmse", 1, nmse, ""},
                    {0, "tracking_nmse", 7, std::nullopt, "target std 1e-15 rad is below the nMSE floor"},
                    {0, "tracking_nmse", {}, nmse, "mean over 1 of 2 joints; left out: joint 7"},
                    {0, "learner_us_per_update", {}, microseconds, ""},
                    {0, "sim_seconds_per_wall_second", {}, 1000.0 / microseconds, ""}};
  return result;
}

void write_database(const std::string& file, const std::string& sweep, double nmse, double microseconds) {
  ResultsStore store = ResultsStore::open(file, ResultsStore::Mode::read_write);
  const RegisteredRun run = store.insert_sweep_run(make_sweep(sweep), {{"k1", {{"seed", 1}}, {{"seed", 1}}, 1}});
  store.insert_job_batch({{"k1"}, {make_result("k1", nmse, microseconds)}, {}}, sweep);
  store.update_run_finished(run.run_id, "complete", 1, 0, make_utc_timestamp());
}

TEST_F(ResultsStoreV2Test, UndefinedValuesAreNullWithTheirReasonAndMetricInfoExplainsNames) {
  write_database(path("r.db"), "s", 0.01, 20.0);
  EXPECT_EQ(test_support::query_rows_read_only(path("r.db"), "SELECT typeof(value), reason FROM metrics WHERE joint = 7"),
            std::vector<std::string>{"null|target std 1e-15 rad is below the nMSE floor"});
  EXPECT_EQ(test_support::query_rows_read_only(path("r.db"), "SELECT unit, direction, kind FROM metric_info WHERE name = 'learner_us_per_update'"),
            std::vector<std::string>{"µs|lower|timing"});
  EXPECT_EQ(test_support::query_rows_read_only(path("r.db"), "SELECT value, reason, unit, kind FROM job_metrics WHERE name = 'tracking_nmse' "
                                        "AND joint IS NULL"),
            std::vector<std::string>{"0.01|mean over 1 of 2 joints; left out: joint 7|1|result"});
  // Only REAL or NULL values: text smuggled in by hand is refused by the schema.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path("r.db").c_str(), &db), SQLITE_OK);
  EXPECT_NE(sqlite3_exec(db, "INSERT INTO metrics (job_id, name, value) VALUES (1, 'x', 'abc')", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const ResultsStore reader = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_only);
  const auto metrics = reader.find_metrics(reader.find_job("k1")->id);
  ASSERT_EQ(metrics.size(), 5u);
  const auto& joint7 = metrics[4];  // ordered by name, joint: tracking_nmse NULL, 1, 7
  EXPECT_EQ(joint7.joint, 7);
  EXPECT_FALSE(joint7.value.has_value());
  EXPECT_EQ(reader.find_metric_info().size(), 3u);
}

TEST_F(ResultsStoreV2Test, MergeOfRunsDifferingOnlyInTimingHasNoConflicts) {
  write_database(path("a.db"), "s", 0.01, 20.0);
  write_database(path("b.db"), "s", 0.01, 35.0);  // slower machine, same results
  write_database(path("c.db"), "s", 0.02, 20.0);  // a different result
  ResultsStore out = ResultsStore::open(path("out.db"), ResultsStore::Mode::read_write);
  out.merge_from(path("a.db"));
  const MergeReport timing_only = out.merge_from(path("b.db"));
  EXPECT_TRUE(timing_only.conflicts.empty());
  EXPECT_EQ(timing_only.jobs_identical, 1);
  const MergeReport result_changed = out.merge_from(path("c.db"));
  EXPECT_EQ(result_changed.conflicts.size(), 1u);
  EXPECT_EQ(out.find_metric_info().size(), 3u);  // copied along
}

TEST_F(ResultsStoreV2Test, SweepsWhoseNamesSanitiseAlikeGetTwoViews) {
  EXPECT_NE(make_sweep_view_name("a-b"), make_sweep_view_name("a_b"));
  EXPECT_EQ(make_sweep_view_name("a_b"), "sweep_a_b");
  write_database(path("r.db"), "a-b", 0.01, 20.0);
  {
    ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
    const RegisteredRun run = store.insert_sweep_run(make_sweep("a_b"), {{"k2", {{"seed", 2}}, {{"seed", 2}}, 2}});
    store.insert_job_batch({{"k2"}, {make_result("k2", 0.03, 20.0)}, {}}, "a_b");
    store.update_run_finished(run.run_id, "complete", 1, 0, make_utc_timestamp());
  }
  EXPECT_EQ(test_support::query_rows_read_only(path("r.db"), "SELECT key, tracking_nmse FROM " + make_sweep_view_name("a-b")),
            std::vector<std::string>{"k1|0.01"});
  EXPECT_EQ(test_support::query_rows_read_only(path("r.db"), "SELECT key, tracking_nmse FROM sweep_a_b"), std::vector<std::string>{"k2|0.03"});
}

// The version-1 schema as released (migration 1), with a NULL metric and its generated view.
const char* kVersion1Database = R"sql(
PRAGMA application_id = 1095912774;
CREATE TABLE sweeps (id INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE, description TEXT NOT NULL DEFAULT '',
  spec_text TEXT NOT NULL, spec_hash TEXT NOT NULL, started_at TEXT NOT NULL, finished_at TEXT,
  armfarm_version TEXT, git_commit TEXT, git_dirty INTEGER, compiler TEXT, simbody_version TEXT, host TEXT);
CREATE TABLE runs (id INTEGER PRIMARY KEY, sweep_id INTEGER NOT NULL REFERENCES sweeps(id) ON DELETE CASCADE,
  started_at TEXT NOT NULL, finished_at TEXT, status TEXT NOT NULL CHECK (status IN ('running', 'complete', 'interrupted')),
  shard TEXT, jobs_total INTEGER NOT NULL, jobs_skipped INTEGER, jobs_run INTEGER, armfarm_version TEXT, git_commit TEXT, host TEXT);
CREATE TABLE jobs (id INTEGER PRIMARY KEY, key TEXT NOT NULL UNIQUE, sweep TEXT NOT NULL, params TEXT NOT NULL,
  config TEXT NOT NULL, status TEXT NOT NULL CHECK (status IN ('pending', 'running', 'done', 'failed', 'diverged', 'timeout')),
  message TEXT, seed INTEGER NOT NULL, end_time REAL, wall_seconds REAL, started_at TEXT, finished_at TEXT,
  attempts INTEGER NOT NULL DEFAULT 0);
CREATE TABLE sweep_jobs (sweep_id INTEGER NOT NULL REFERENCES sweeps(id) ON DELETE CASCADE,
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE, position INTEGER NOT NULL, params TEXT NOT NULL,
  PRIMARY KEY (sweep_id, job_id));
CREATE INDEX sweep_jobs_by_job ON sweep_jobs(job_id);
CREATE TABLE metrics (job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE, name TEXT NOT NULL, joint INTEGER, value REAL);
CREATE UNIQUE INDEX metrics_by_job ON metrics(job_id, name, IFNULL(joint, 0));
CREATE INDEX metrics_by_name ON metrics(name, joint);
CREATE TABLE series (job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE, name TEXT NOT NULL,
  columns TEXT NOT NULL, rows INTEGER NOT NULL, dtype TEXT NOT NULL DEFAULT 'f64le', layout TEXT NOT NULL DEFAULT 'column-major',
  codec TEXT NOT NULL DEFAULT 'zstd', raw_bytes INTEGER NOT NULL, data BLOB NOT NULL, PRIMARY KEY (job_id, name));
CREATE VIEW job_metrics AS SELECT s.name AS sweep, j.id AS job_id, j.key AS key, j.status AS status, j.seed AS seed,
  sj.params AS params, m.name AS name, m.joint AS joint, m.value AS value
  FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id JOIN metrics m ON m.job_id = j.id;
CREATE VIEW sweep_job_status AS SELECT s.name AS sweep, j.id AS job_id, j.key AS key, j.status AS status,
  j.message AS message, j.seed AS seed, sj.params AS params, j.wall_seconds AS wall_seconds, j.end_time AS end_time
  FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id;
INSERT INTO sweeps (id, name, spec_text, spec_hash, started_at) VALUES (1, 'old-sweep', '{}', 'h', '2026-01-01T00:00:00.000Z');
INSERT INTO jobs (id, key, sweep, params, config, status, seed) VALUES (1, 'k1', 'old-sweep', '{"seed":1}', '{"seed":1}', 'done', 1);
INSERT INTO sweep_jobs VALUES (1, 1, 0, '{"seed":1}');
INSERT INTO metrics VALUES (1, 'tracking_nmse', 1, 0.25), (1, 'tracking_nmse', 7, NULL), (1, 'tracking_nmse', NULL, 1e25);
CREATE VIEW sweep_old_sweep AS SELECT j.id AS job_id, (SELECT m.value FROM metrics m WHERE m.job_id = j.id
  AND m.name = 'tracking_nmse' AND m.joint = 1) AS tracking_nmse_j1 FROM jobs j;
PRAGMA user_version = 1;
)sql";

TEST_F(ResultsStoreV2Test, VersionOneDatabaseOpensReadOnlyAndMigratesWhenWritten) {
  execute_as_user(path("v1.db"), kVersion1Database);
  {
    const ResultsStore reader = ResultsStore::open(path("v1.db"), ResultsStore::Mode::read_only);
    EXPECT_EQ(reader.schema_version(), kResultsSchemaVersion);  // a migrated in-memory copy
    const auto metrics = reader.find_metrics(1);
    ASSERT_EQ(metrics.size(), 3u);
    EXPECT_FALSE(metrics[2].value.has_value());
    EXPECT_NE(metrics[2].reason.find("schema version 1"), std::string::npos);
  }
  EXPECT_EQ(test_support::query_rows_read_only(path("v1.db"), "PRAGMA user_version"), std::vector<std::string>{"1"});  // file untouched
  // Merging from an old file reads a migrated copy.
  {
    ResultsStore out = ResultsStore::open(path("out.db"), ResultsStore::Mode::read_write);
    EXPECT_EQ(out.merge_from(path("v1.db")).jobs_added, 1);
    EXPECT_EQ(out.find_metrics(out.find_job("k1")->id).size(), 3u);
  }
  {
    ResultsStore writer = ResultsStore::open(path("v1.db"), ResultsStore::Mode::read_write);
    EXPECT_EQ(writer.schema_version(), kResultsSchemaVersion);
  }
  EXPECT_EQ(test_support::query_rows_read_only(path("v1.db"), "SELECT value FROM metrics WHERE joint = 1"), std::vector<std::string>{"0.25"});
  EXPECT_EQ(test_support::query_rows_read_only(path("v1.db"), "SELECT count(*) FROM metric_info"), std::vector<std::string>{"0"});
  // The generated view is regenerated under its version-2 name; the old one is gone.
  EXPECT_EQ(test_support::query_rows_read_only(path("v1.db"), "SELECT tracking_nmse_j1 FROM " + make_sweep_view_name("old-sweep")),
            std::vector<std::string>{"0.25"});
  EXPECT_TRUE(test_support::query_rows_read_only(path("v1.db"), "SELECT name FROM sqlite_master WHERE name = 'sweep_old_sweep'").empty());
}

// open_checked words a file SQLite cannot read with SQLite's reason, taken from the error's
// detail field (not cut out of its text): the whole line, byte for byte.
TEST_F(ResultsStoreV2Test, AFileSqliteCannotReadIsRefusedWithSqlitesReasonInParentheses) {
  std::ofstream(path("text.db")) << "this is not a database, just some text that is long enough to matter\n"
                                 << std::string(2000, 'x');
  for (const ResultsStore::Mode mode : {ResultsStore::Mode::read_write, ResultsStore::Mode::read_only}) {
    try {
      ResultsStore::open(path("text.db"), mode);
      ADD_FAILURE() << "a text file opened as a database";
    } catch (const StoreError& e) {
      EXPECT_EQ(std::string(e.what()), path("text.db") + ": not a readable SQLite database (query failed: file is not a database)");
    }
  }
}

// The connection's errors carry the file, the detail and SQLite's result code as fields.
TEST_F(ResultsStoreV2Test, ASqliteRefusalCarriesItsDetailAndResultCode) {
  SqliteConnection connection(path("fields.db"), false);
  try {
    connection.execute("SELECT * FROM no_such_table");
    ADD_FAILURE() << "a query of a missing table ran";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.detail(), "no such table: no_such_table");
    EXPECT_EQ(std::string(e.what()), path("fields.db") + ": " + e.detail());
    EXPECT_EQ(e.sqlite_code(), SQLITE_ERROR);
  }
  try {
    connection.query_int("SELECT 1 WHERE 0");
    ADD_FAILURE() << "a query without a row gave an integer";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.detail(), "no result for SELECT 1 WHERE 0");
    EXPECT_EQ(e.sqlite_code(), 0);
  }
}

// Switching a fresh file to WAL while another connection reads it is refused with SQLITE_BUSY
// (here at once: the busy timeout is set to 0), the code open_checked's retry tests rather than
// the words "locked"; the open succeeds once the other connection lets go.
TEST_F(ResultsStoreV2Test, AFreshFileHeldByAReaderRefusesWalWithBusyAndOpensOnceItIsFree) {
  const std::string file = path("held.db");
  sqlite3* reader = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &reader), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(reader, "BEGIN; SELECT count(*) FROM sqlite_master;", nullptr, nullptr, nullptr), SQLITE_OK);
  {
    SqliteConnection writer(file, false);
    sqlite3_busy_timeout(writer.handle(), 0);
    try {
      writer.execute("PRAGMA journal_mode = WAL");
      ADD_FAILURE() << "WAL was set while another connection read the file";
    } catch (const StoreError& e) {
      EXPECT_EQ(e.sqlite_code() & 0xff, SQLITE_BUSY) << e.what();
      EXPECT_EQ(std::string(e.what()), file + ": database is locked");
    }
  }
  std::thread release([reader] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    sqlite3_exec(reader, "COMMIT", nullptr, nullptr, nullptr);
  });
  EXPECT_NO_THROW(ResultsStore::open(file, ResultsStore::Mode::read_write));
  release.join();
  sqlite3_close(reader);
  EXPECT_EQ(test_support::query_rows_read_only(file, "PRAGMA journal_mode"), std::vector<std::string>{"wal"});
}

}  // namespace
}  // namespace armfarm
