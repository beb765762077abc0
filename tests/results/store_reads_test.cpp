// The store's reads: every table written reads back; readers query while the writer commits
// and never see a done job without its metrics.
#include "support/results_store_fixture.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>

namespace armfarm {
namespace {

using test_support::make_jobs;
using test_support::make_result;
using test_support::make_sweep;
using test_support::ResultsStoreTest;

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

}  // namespace
}  // namespace armfarm
