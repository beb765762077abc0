// The runner reports a job only once its result is committed: the log's `done` lines are the
// database's done jobs, and the summary names the run's best and worst job by its main metric.
#include "runner/execution/fake_job.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <sstream>

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
