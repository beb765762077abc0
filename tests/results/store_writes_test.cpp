// The store's writes: a rerun replaces a job's metrics and keeps its done status for resume;
// jobs are shared across sweeps by key, each sweep with its own parameters.
#include "support/results_store_fixture.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace armfarm {
namespace {

using test_support::make_jobs;
using test_support::make_result;
using test_support::make_sweep;
using test_support::ResultsStoreTest;

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

}  // namespace
}  // namespace armfarm
