// The results store: write/read round trips, resume bookkeeping, the per-sweep view answering
// "nMSE of joint 2 by init_D" in plain SQL, merges, concurrent readers, and clear errors for
// files that are not (or not yet) armfarm databases.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include "support/sqlite_rows.hpp"
#include <sqlite3.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class ResultsStoreTest : public test_support::ScratchFolderTest {
 protected:
  ResultsStoreTest() : ScratchFolderTest("store") {}
};


SweepRegistration make_sweep(const std::string& name, const std::string& hash = "h1") {
  SweepRegistration sweep;
  sweep.name = name;
  sweep.description = "a test sweep";
  sweep.spec_text = "{\"name\": \"" + name + "\"}";
  sweep.spec_hash = hash;
  sweep.started_at = make_utc_timestamp();
  sweep.provenance.armfarm_version = "0.1.0";
  sweep.provenance.host = "testhost";
  return sweep;
}

std::vector<JobRegistration> make_jobs(int n) {
  std::vector<JobRegistration> jobs;
  for (int i = 0; i < n; ++i) {
    const double init_D = 10.0 * (i + 1);
    jobs.push_back({"key" + std::to_string(i), {{"learning.lwpr.init_D", init_D}},
                    {{"learning", {{"lwpr", {{"init_D", init_D}}}}}, {"seed", i}}, i});
  }
  return jobs;
}

JobResultRecord make_result(const std::string& key, double scale) {
  JobResultRecord result;
  result.key = key;
  result.status = "done";
  result.end_time = 20.0;
  result.wall_seconds = 1.5;
  result.started_at = result.finished_at = make_utc_timestamp();
  result.metrics = {{0, "tracking_nmse", 1, 0.1 * scale, ""}, {0, "tracking_nmse", 2, 0.2 * scale, ""}, {0, "test_nmse", {}, 0.3 * scale, ""}};
  Eigen::MatrixXd rows(3, 2);
  rows << 0.0, scale, 0.1, 2 * scale, 0.2, 3 * scale;
  result.series = {{0, "POS", {"t", "q1"}, rows}};
  return result;
}

TEST_F(ResultsStoreTest, WritesAndReadsBackEveryTable) {
  ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  EXPECT_EQ(store.schema_version(), kResultsSchemaVersion);
  const RegisteredRun run = store.insert_sweep_run(make_sweep("s"), make_jobs(3));
  EXPECT_EQ(run.status_by_key.size(), 3u);
  EXPECT_EQ(run.status_by_key.at("key1"), "pending");
  store.insert_job_batch({{"key0", "key1"}, {make_result("key0", 1.0)}, {"key1"}}, "s");
  store.update_run_finished(run.run_id, "complete", 1, 0, make_utc_timestamp());

  const ResultsStore reader = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_only);
  const std::vector<SweepRecord> sweeps = reader.find_sweeps();
  ASSERT_EQ(sweeps.size(), 1u);
  EXPECT_EQ(sweeps[0].provenance.host, "testhost");
  EXPECT_TRUE(sweeps[0].finished_at.has_value());
  const std::vector<JobRecord> jobs = reader.find_jobs("s");
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0].status, "done");
  EXPECT_EQ(jobs[0].attempts, 1);
  EXPECT_EQ(jobs[1].status, "pending");  // started, then abandoned
  EXPECT_EQ(jobs[2].status, "pending");
  EXPECT_DOUBLE_EQ(jobs[1].params["learning.lwpr.init_D"].get<double>(), 20.0);
  EXPECT_EQ(jobs[2].config["seed"], 2);

  const std::vector<MetricRecord> metrics = reader.find_metrics(jobs[0].id);
  ASSERT_EQ(metrics.size(), 3u);
  EXPECT_EQ(metrics[0].name, "test_nmse");
  EXPECT_FALSE(metrics[0].joint.has_value());
  EXPECT_EQ(metrics[2].joint, 2);
  EXPECT_DOUBLE_EQ(metrics[2].value.value(), 0.2);
  const auto series = reader.find_series(jobs[0].id, "POS");
  ASSERT_TRUE(series.has_value());
  EXPECT_EQ(series->columns, (std::vector<std::string>{"t", "q1"}));
  EXPECT_DOUBLE_EQ(series->rows(2, 1), 3.0);
  EXPECT_FALSE(reader.find_series(jobs[0].id, "TOR").has_value());
  EXPECT_EQ(reader.count_jobs_by_status("s").at("pending"), 2);
  EXPECT_EQ(reader.find_job_keys("key").size(), 3u);
  EXPECT_EQ(reader.check_integrity(), "ok");
}

TEST_F(ResultsStoreTest, RerunReplacesMetricsAndKeepsDoneStatusForResume) {
  ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  store.insert_sweep_run(make_sweep("s"), make_jobs(2));
  store.insert_job_batch({{"key0"}, {make_result("key0", 1.0)}, {}}, "s");
  store.insert_job_batch({{"key0"}, {make_result("key0", 2.0)}, {}}, "s");
  const RegisteredRun again = store.insert_sweep_run(make_sweep("s"), make_jobs(2));
  EXPECT_EQ(again.status_by_key.at("key0"), "done");
  EXPECT_EQ(again.status_by_key.at("key1"), "pending");
  const JobRecord job = *store.find_job("key0");
  EXPECT_EQ(job.attempts, 2);
  const auto metrics = store.find_metrics(job.id);
  ASSERT_EQ(metrics.size(), 3u);  // replaced, not accumulated
  EXPECT_DOUBLE_EQ(metrics[0].value.value(), 0.6);
}

TEST_F(ResultsStoreTest, JobsAreSharedAcrossSweepsByKey) {
  ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  store.insert_sweep_run(make_sweep("a"), make_jobs(2));
  store.insert_job_batch({{"key0"}, {make_result("key0", 1.0)}, {}}, "a");
  std::vector<JobRegistration> other = make_jobs(3);
  other[0].params = {{"seed", 0}};
  const RegisteredRun run = store.insert_sweep_run(make_sweep("b"), other);
  EXPECT_EQ(run.status_by_key.at("key0"), "done");  // reused, not run again
  EXPECT_EQ(store.find_jobs("a").size(), 2u);
  EXPECT_EQ(store.find_jobs("b").size(), 3u);
  EXPECT_EQ(store.find_jobs("b")[0].params, (nlohmann::json{{"seed", 0}}));  // each sweep its own params
  EXPECT_EQ(store.find_jobs("a")[0].params.count("learning.lwpr.init_D"), 1u);
}

TEST_F(ResultsStoreTest, SweepViewAnswersNmseOfJointTwoByInitD) {
  ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  const RegisteredRun run = store.insert_sweep_run(make_sweep("my-sweep"), make_jobs(3));
  store.insert_job_batch({{}, {make_result("key0", 1.0), make_result("key1", 2.0), make_result("key2", 4.0)}, {}},
                         "my-sweep");
  store.update_run_finished(run.run_id, "complete", 3, 0, make_utc_timestamp());
  const std::string view = make_sweep_view_name("my-sweep");
  EXPECT_EQ(view.substr(0, 15), "sweep_my_sweep_");  // '-' was replaced: a hash keeps it unique
  EXPECT_EQ(view.size(), 21u);
  const auto rows = test_support::query_rows_read_only(
      path("r.db"), "SELECT \"learning.lwpr.init_D\", tracking_nmse_j2 FROM " + view + " ORDER BY 1");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], "10.0|0.2");
  EXPECT_EQ(rows[2], "30.0|0.8");
  const auto long_form = test_support::query_rows_read_only(
      path("r.db"),
      "SELECT json_extract(params, '$.\"learning.lwpr.init_D\"'), value FROM job_metrics "
      "WHERE sweep = 'my-sweep' AND name = 'tracking_nmse' AND joint = 2 ORDER BY 1");
  EXPECT_EQ(long_form, rows);
}

TEST_F(ResultsStoreTest, MergeCopiesNewJobsAcceptsIdenticalOnesAndReportsConflicts) {
  {
    ResultsStore a = ResultsStore::open(path("a.db"), ResultsStore::Mode::read_write);
    a.insert_sweep_run(make_sweep("s"), make_jobs(2));
    a.insert_job_batch({{}, {make_result("key0", 1.0)}, {}}, "s");
    ResultsStore b = ResultsStore::open(path("b.db"), ResultsStore::Mode::read_write);
    std::vector<JobRegistration> jobs = make_jobs(3);
    b.insert_sweep_run(make_sweep("s"), jobs);
    b.insert_job_batch({{}, {make_result("key0", 1.0), make_result("key1", 3.0), make_result("key2", 5.0)}, {}}, "s");
    ResultsStore c = ResultsStore::open(path("c.db"), ResultsStore::Mode::read_write);
    c.insert_sweep_run(make_sweep("s"), make_jobs(1));
    c.insert_job_batch({{}, {make_result("key0", 7.0)}, {}}, "s");
  }
  ResultsStore out = ResultsStore::open(path("out.db"), ResultsStore::Mode::read_write);
  const MergeReport first = out.merge_from(path("a.db"));
  EXPECT_EQ(first.jobs_added, 2);
  const MergeReport second = out.merge_from(path("b.db"));
  EXPECT_EQ(second.jobs_identical, 1);  // key0 identical
  EXPECT_EQ(second.jobs_replaced, 1);   // key1 pending in a, done in b
  EXPECT_EQ(second.jobs_added, 1);      // key2
  EXPECT_TRUE(second.conflicts.empty());
  const MergeReport third = out.merge_from(path("c.db"));
  ASSERT_EQ(third.conflicts.size(), 1u);
  EXPECT_NE(third.conflicts[0].find("key0"), std::string::npos);
  EXPECT_EQ(out.find_jobs("s").size(), 3u);
  EXPECT_EQ(out.count_jobs_by_status("s").at("done"), 3);
  EXPECT_DOUBLE_EQ(out.find_metrics(out.find_job("key1")->id)[0].value.value(), 0.9);
  EXPECT_EQ(out.find_series(out.find_job("key2")->id, "POS")->rows(0, 1), 5.0);
}

TEST_F(ResultsStoreTest, ReadersQueryWhileTheWriterCommits) {
  ResultsStore writer = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  const int n = 200;
  writer.insert_sweep_run(make_sweep("s"), make_jobs(n));
  std::atomic<bool> writing{true};
  std::atomic<int> reads{0};
  std::string reader_error;
  std::thread reader([&] {
    try {
      const ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_only);
      int last_done = 0;
      while (writing.load() || reads.load() == 0) {
        const auto counts = store.count_jobs_by_status("s");
        const int done = counts.count("done") ? counts.at("done") : 0;
        if (done < last_done) reader_error = "done count went backwards";
        last_done = done;
        const auto metrics = store.find_sweep_metrics("s");
        if (metrics.size() < 3u * static_cast<std::size_t>(done)) {  // read after the counts: never fewer
          reader_error = "metrics missing for done jobs";
        }
        ++reads;
      }
    } catch (const std::exception& e) {
      reader_error = e.what();
    }
  });
  for (int i = 0; i < n; ++i) writer.insert_job_batch({{}, {make_result("key" + std::to_string(i), i)}, {}}, "s");
  writing = false;
  reader.join();
  EXPECT_EQ(reader_error, "");
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(writer.count_jobs_by_status("s").at("done"), n);
}

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
