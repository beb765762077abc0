// The parallel runner with the fake job: resume, failures recorded while the sweep goes on,
// timeouts, stop requests, identical metrics whatever -j, shard + merge equal to one run.
#include "runner/execution/sweep_runner.hpp"

#include "support/fake_job.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <atomic>
#include <filesystem>
#include <map>
#include <thread>
#include <set>
#include <sstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class SweepRunnerTest : public test_support::ScratchFolderTest {
 protected:
  SweepRunnerTest() : ScratchFolderTest("runner") {}
  ExpandedSweep expand(const std::string& text) const {
    return expand_sweep(parse_sweep_spec(text, "test.json", ".", schema_), schema_);
  }
  RunSummary run(const ExpandedSweep& sweep, const std::string& db, int threads, bool force = false,
                 Shard shard = {}) const {
    RunOptions options;
    options.db_path = path(db);
    options.threads = threads;
    options.force = force;
    options.shard = shard;
    const std::atomic<bool> no_stop{false};
    return run_sweep(sweep, make_fake_job_executor(), options, no_stop);
  }

  JobConfigSchema schema_ = make_fake_job_config_schema();
};

const char* kSpec = R"({"name": "s", "base": {"fake": {"sleep_ms": 1}}, "sweep": {
    "grid": {"learning.lwpr.init_D": [10, 25, 50, 100], "control.gain_scale": [0.5, 1]}, "repeat": 2}})";

// key -> (status, metric values in order, POS series)
using Snapshot = std::map<std::string, std::tuple<std::string, std::vector<double>, Eigen::MatrixXd>>;

Snapshot read_snapshot(const std::string& db, const std::string& sweep) {
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  Snapshot snapshot;
  for (const JobRecord& job : store.find_jobs(sweep)) {
    std::vector<double> values;
    for (const MetricRecord& m : store.find_metrics(job.id)) values.push_back(m.value.value_or(std::nan("")));
    const auto pos = store.find_series(job.id, "POS");
    snapshot[job.key] = {job.status, values, pos ? pos->rows : Eigen::MatrixXd()};
  }
  return snapshot;
}

TEST_F(SweepRunnerTest, ResumeSkipsDoneJobsAndForceRunsThemAgain) {
  const ExpandedSweep sweep = expand(kSpec);
  const RunSummary first = run(sweep, "r.db", 2);
  EXPECT_EQ(first.done, 16);
  EXPECT_TRUE(first.all_done());
  const RunSummary second = run(sweep, "r.db", 2);
  EXPECT_EQ(second.skipped, 16);
  EXPECT_EQ(second.run, 0);
  const ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_only);
  for (const JobRecord& job : store.find_jobs("s")) EXPECT_EQ(job.attempts, 1);
  const RunSummary forced = run(sweep, "r.db", 2, true);
  EXPECT_EQ(forced.run, 16);
  EXPECT_EQ(store.find_jobs("s")[0].attempts, 2);
}

TEST_F(SweepRunnerTest, ChangingOneValueRerunsOnlyTheJobsItChanges) {
  run(expand(kSpec), "r.db", 2);
  std::string changed = kSpec;
  changed.replace(changed.find("100]"), 3, "200");
  const RunSummary summary = run(expand(changed), "r.db", 2);
  EXPECT_EQ(summary.skipped, 12);
  EXPECT_EQ(summary.run, 4);
  const ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_only);
  EXPECT_EQ(store.find_jobs("s").size(), 16u);  // the sweep now lists its new jobs only
}

TEST_F(SweepRunnerTest, FailuresAreRecordedAndTheSweepGoesOn) {
  const ExpandedSweep sweep = expand(R"({"name": "f", "base": {"fake": {"sleep_ms": 0}}, "sweep": {"zip": {
      "fake.fail": [false, true, false, false, false], "fake.throw": [false, false, true, false, false],
      "fake.diverge": [false, false, false, true, false], "fake.hang": [false, false, false, false, true]}}})");
  RunOptions options;
  options.db_path = path("f.db");
  options.threads = 2;
  options.timeout_seconds = 0.2;
  const std::atomic<bool> no_stop{false};
  const RunSummary summary = run_sweep(sweep, make_fake_job_executor(), options, no_stop);
  EXPECT_EQ(summary.done, 1);
  EXPECT_EQ(summary.failed, 2);
  EXPECT_EQ(summary.diverged, 1);
  EXPECT_EQ(summary.timeout, 1);
  EXPECT_FALSE(summary.all_done());
  const ResultsStore store = ResultsStore::open(path("f.db"), ResultsStore::Mode::read_only);
  const auto jobs = store.find_jobs("f");
  ASSERT_EQ(jobs.size(), 5u);
  EXPECT_EQ(jobs[1].message, "fake job asked to fail");
  EXPECT_EQ(jobs[2].message, "exception: fake job asked to throw");
  EXPECT_EQ(jobs[3].status, "diverged");
  EXPECT_DOUBLE_EQ(*jobs[3].end_time, 2.0);
  EXPECT_EQ(jobs[4].status, "timeout");
  EXPECT_NE(jobs[4].message.find("timeout of 0.2 s"), std::string::npos);
  // Failed jobs run again on resume; the done one does not.
  const RunSummary again = run_sweep(sweep, make_fake_job_executor(), options, no_stop);
  EXPECT_EQ(again.skipped, 1);
  EXPECT_EQ(again.run, 4);
}

TEST_F(SweepRunnerTest, AStopRequestLeavesUnfinishedJobsPendingForResume) {
  const ExpandedSweep sweep = expand(R"({"name": "h", "base": {"fake": {"hang": true}}, "sweep": {"repeat": 4}})");
  RunOptions options;
  options.db_path = path("h.db");
  options.threads = 2;
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    stop = true;
  });
  const RunSummary summary = run_sweep(sweep, make_fake_job_executor(), options, stop);
  stopper.join();
  EXPECT_TRUE(summary.interrupted);
  EXPECT_EQ(summary.abandoned, 4);
  EXPECT_EQ(summary.run, 0);
  const ResultsStore store = ResultsStore::open(path("h.db"), ResultsStore::Mode::read_only);
  EXPECT_EQ(store.count_jobs_by_status("h").at("pending"), 4);
  EXPECT_FALSE(store.find_sweep("h")->finished_at.has_value());
  EXPECT_EQ(store.check_integrity(), "ok");
}

// The jobs of `sweep` that run now, 0 while the database cannot be read yet.
int count_running_jobs(const std::string& db_path, const std::string& sweep) {
  try {
    const ResultsStore store = ResultsStore::open(db_path, ResultsStore::Mode::read_only);
    const std::map<std::string, int> counts = store.count_jobs_by_status(sweep);
    const auto running = counts.find("running");
    return running == counts.end() ? 0 : running->second;
  } catch (const std::exception&) {
    return 0;
  }
}

// Slurm's warning (a stop with a grace): the job expected to end within the grace finishes, the
// one that cannot is stopped at once and stays pending, not failed; a stop at once (SIGTERM)
// waits for neither.
TEST_F(SweepRunnerTest, AStopGraceLetsTheJobsThatCanEndInTimeFinish) {
  const ExpandedSweep sweep = expand(R"({"name": "g", "sweep": {"zip": {"fake.sleep_ms": [1500, 60000]}}})");
  for (const bool at_once : {false, true}) {
    RunOptions options;
    options.db_path = path(at_once ? "at_once.db" : "grace.db");
    options.threads = 2;
    options.stop_grace_seconds = 20.0;
    options.job_seconds = calc_job_seconds(sweep, make_fake_job_cost_function());
    ASSERT_EQ(options.job_seconds.size(), 2u);
    EXPECT_NEAR(options.job_seconds[0], 1.51, 1e-9);  // the sleep and 0.01 s
    EXPECT_NEAR(options.job_seconds[1], 60.01, 1e-9);
    const std::atomic<bool> stop_at_once{at_once};
    options.stop_at_once = &stop_at_once;
    std::atomic<bool> stop{false};
    // The stop comes once both jobs run (a fixed delay raced the jobs' start on a loaded machine).
    std::thread stopper([&] {
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (std::chrono::steady_clock::now() < give_up && count_running_jobs(options.db_path, "g") < 2) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      stop = true;
    });
    const auto start = std::chrono::steady_clock::now();
    const RunSummary summary = run_sweep(sweep, make_fake_job_executor(), options, stop);
    stopper.join();
    EXPECT_TRUE(summary.interrupted);
    EXPECT_EQ(summary.failed + summary.timeout, 0);
    EXPECT_EQ(summary.done, at_once ? 0 : 1);
    EXPECT_EQ(summary.finished_in_grace, at_once ? 0 : 1);
    EXPECT_EQ(summary.abandoned, at_once ? 2 : 1);
    // The long job did not hold the run up to the end of the grace.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 15.0);
    const ResultsStore store = ResultsStore::open(options.db_path, ResultsStore::Mode::read_only);
    const std::vector<JobRecord> jobs = store.find_jobs("g");
    ASSERT_EQ(jobs.size(), 2u);
    EXPECT_EQ(jobs[0].status, at_once ? "pending" : "done");
    EXPECT_EQ(jobs[1].status, "pending");
  }
}

// A stop after the last job finished interrupted nothing: the run is complete.
TEST_F(SweepRunnerTest, AStopAfterEveryJobIsNotAnInterruption) {
  const ExpandedSweep sweep = expand(R"({"name": "a", "base": {"fake": {"sleep_ms": 0}}, "sweep": {"repeat": 2}})");
  RunOptions options;
  options.db_path = path("a.db");
  options.threads = 1;
  const RunSummary first = run_sweep(sweep, make_fake_job_executor(), options, std::atomic<bool>{false});
  ASSERT_TRUE(first.all_done());
  const RunSummary stopped = run_sweep(sweep, make_fake_job_executor(), options, std::atomic<bool>{true});
  EXPECT_EQ(stopped.skipped, 2);
  EXPECT_FALSE(stopped.interrupted);
  EXPECT_TRUE(stopped.all_done());
}

TEST_F(SweepRunnerTest, MetricsAreIdenticalWhateverTheThreadCount) {
  const ExpandedSweep sweep = expand(kSpec);
  run(sweep, "j1.db", 1);
  run(sweep, "j2.db", 2);
  run(sweep, "j4.db", 4);
  const Snapshot one = read_snapshot(path("j1.db"), "s");
  ASSERT_EQ(one.size(), 16u);
  EXPECT_EQ(one, read_snapshot(path("j2.db"), "s"));
  EXPECT_EQ(one, read_snapshot(path("j4.db"), "s"));
}

TEST_F(SweepRunnerTest, ShardsPartitionTheSweepAndMergeIntoTheUnshardedResult) {
  const ExpandedSweep sweep = expand(kSpec);
  run(sweep, "all.db", 2);
  int total = 0;
  for (int i = 1; i <= 3; ++i) {
    const RunSummary summary = run(sweep, "shard" + std::to_string(i) + ".db", 1, false, {i, 3});
    EXPECT_GT(summary.jobs_in_shard, 0);
    total += summary.jobs_in_shard;
  }
  EXPECT_EQ(total, 16);
  ResultsStore merged = ResultsStore::open(path("merged.db"), ResultsStore::Mode::read_write);
  for (int i = 1; i <= 3; ++i) {
    const MergeReport report = merged.merge_from(path("shard" + std::to_string(i) + ".db"));
    EXPECT_TRUE(report.conflicts.empty());
  }
  // Merging a shard again is harmless: identical rows.
  const MergeReport again = merged.merge_from(path("shard1.db"));
  EXPECT_TRUE(again.conflicts.empty());
  EXPECT_EQ(again.jobs_added, 0);
  EXPECT_EQ(read_snapshot(path("merged.db"), "s"), read_snapshot(path("all.db"), "s"));
}

TEST(Shard, Parses) {
  EXPECT_EQ(parse_shard("2/4").index, 2);
  EXPECT_EQ(parse_shard("2/4").count, 4);
  for (const char* bad : {"0/4", "5/4", "2", "a/b", "2/4x", "1/0"}) EXPECT_THROW(parse_shard(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/execution/sweep_runner_progress_test.cpp:
// The runner reports a job only once its result is committed: the log's `done` lines are the
// database's done jobs, and the summary names the run's best and worst job by its main metric.

namespace armfarm {
namespace {

namespace fs = std::filesystem;

TEST(SweepRunnerProgress, DoneLinesAreTheCommittedJobsAndTheHeadlineIsTheirBestAndWorst) {
  const fs::path folder = fs::temp_directory_path() / ("armfarm_progress_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  const JobConfigSchema schema = make_fake_job_config_schema();
  const ExpandedSweep sweep = expand_sweep(
      parse_sweep_spec(R"({"name": "p", "base": {"fake": {"sleep_ms": 2}}, "sweep": {"zip": {
          "learning.lwpr.init_D": [10, 20, 40, 80, 160], "fake.fail": [false, false, true, false, false]}}})",
                       "p.json", ".", schema),
      schema);
  std::ostringstream log;
  RunOptions options;
  options.db_path = (folder / "p.db").string();
  options.threads = 2;
  options.progress.style = ProgressStyle::lines;
  options.progress.heartbeat_seconds = 0;
  options.progress_out = &log;
  const std::atomic<bool> no_stop{false};
  const RunSummary summary = run_sweep(sweep, make_fake_job_executor(), options, no_stop);
  EXPECT_EQ(summary.done, 4);
  EXPECT_EQ(summary.failed, 1);
  EXPECT_EQ(summary.not_saved, 0);
  EXPECT_TRUE(summary.write_error.empty());

  std::set<std::string> printed_done;
  std::istringstream lines(log.str());
  for (std::string line; std::getline(lines, line);) {
    if (line.find("] done ") != std::string::npos) printed_done.insert(line.substr(line.find("done") + 9, 8));
  }
  std::set<std::string> stored_done;
  std::map<std::string, double> test_nmse;  // short key -> same_run_test_nmse
  const ResultsStore store = ResultsStore::open(options.db_path, ResultsStore::Mode::read_only);
  for (const JobRecord& job : store.find_jobs("p")) {
    if (job.status != "done") continue;
    stored_done.insert(job.key.substr(0, 8));
    for (const MetricRecord& m : store.find_metrics(job.id)) {
      if (m.name == "same_run_test_nmse") test_nmse[job.key.substr(0, 8)] = *m.value;
    }
  }
  EXPECT_EQ(printed_done, stored_done) << log.str();

  // The fake job's only job-level result metric with a direction is same_run_test_nmse (lower).
  ASSERT_TRUE(summary.headline);
  EXPECT_EQ(summary.headline->metric, "same_run_test_nmse");
  EXPECT_EQ(summary.headline->jobs, 4);
  const auto [lowest, highest] = std::minmax_element(test_nmse.begin(), test_nmse.end(),
                                                     [](const auto& a, const auto& b) { return a.second < b.second; });
  EXPECT_EQ(summary.headline->best_label.substr(0, 8), lowest->first);
  EXPECT_EQ(summary.headline->worst_label.substr(0, 8), highest->first);
  EXPECT_DOUBLE_EQ(summary.headline->best, lowest->second);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
