// The runner's trajectory sharing: jobs of a sweep with equal trajectory inputs and model share
// one build (the key ignores gains, learner and integrator), the shared outcome is bit-identical
// to a fresh executor's, and the cache builds once per key even under concurrent use.
#include "engine/experiment/metric_catalog.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/execution/trajectory_cache.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <map>
#include <stdexcept>
#include <cstring>
#include <set>
#include <thread>
#include <vector>

namespace armfarm {
namespace {

ExpandedSweep expand_text(const std::string& text) {
  const JobConfigSchema schema = make_experiment_config_schema();
  return expand_sweep(parse_sweep_spec(text, "inline.json", ".", schema), schema);
}

const char* const kSweep = R"({"name": "share", "base": {"active_joints": [1, 2, 4],
    "trajectory": {"kind": "reaching", "reaching": {"reaches": 3, "points_per_reach": 50}},
    "learning": {"mode": "online", "heldout_segments": 2}},
  "sweep": {"grid": {"control.gain_scale": [0.2, 1.0], "learning.lwpr.init_D": [0.05, 0.5], "seed": [0, 1]}}})";

TEST(TrajectoryCache, KeyIsTheTrajectoryInputsAndTheModel) {
  const ExpandedSweep sweep = expand_text(kSweep);
  ASSERT_EQ(sweep.jobs.size(), 8u);
  std::set<std::string> keys;
  std::map<std::int64_t, std::set<std::string>> keys_by_seed;
  for (const ExpandedJob& job : sweep.jobs) {
    const std::string key = make_trajectory_key(job.config());
    keys.insert(key);
    keys_by_seed[job.config().at("seed").get<std::int64_t>()].insert(key);
    EXPECT_EQ(key.find("gain_scale"), std::string::npos) << key;
    EXPECT_NE(key.find("xxh3-128:"), std::string::npos) << "the model enters by its content hash: " << key;
  }
  EXPECT_EQ(keys.size(), 2u);  // one per seed: the seed draws the reaching targets
  EXPECT_EQ(keys_by_seed[0].size(), 1u);
  EXPECT_EQ(keys_by_seed[1].size(), 1u);
  nlohmann::json other_model = sweep.jobs[0].config();
  other_model["inputs"]["model"]["hash"] = "00000000000000000000000000000000";
  EXPECT_NE(make_trajectory_key(other_model), make_trajectory_key(sweep.jobs[0].config()));
  nlohmann::json other_dt = sweep.jobs[0].config();
  other_dt["dt"] = 0.005;
  EXPECT_NE(make_trajectory_key(other_dt), make_trajectory_key(sweep.jobs[0].config()));
  // Task-space targets are solved for the end effector: another point, another trajectory.
  nlohmann::json other_tip = sweep.jobs[0].config();
  other_tip["end_effector"]["offset"] = {0.0, 0.0, 0.05};
  EXPECT_NE(make_trajectory_key(other_tip), make_trajectory_key(sweep.jobs[0].config()));
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(TrajectoryCache, SweepOnSharedTrajectoriesMatchesFreshExecutorsBitForBit) {
  const ExpandedSweep sweep = expand_text(kSweep);
  const JobExecutor shared = make_experiment_executor();  // one for the sweep: shares builds
  for (std::size_t i = 0; i < 4; ++i) {
    const ExpandedJob& job = sweep.jobs[i];
    // a: the configuration the expansion checked; b: the JSON read again, by an executor that
    // builds its own trajectories.
    const JobOutcome a = shared(job.config(), job.checked.get(), JobControl{});
    const JobOutcome b = make_experiment_executor()(job.config(), nullptr, JobControl{});
    ASSERT_EQ(a.status, JobStatus::done) << a.message;
    ASSERT_EQ(a.metrics.size(), b.metrics.size());
    for (std::size_t m = 0; m < a.metrics.size(); ++m) {
      if (find_metric_info(a.metrics[m].name).kind == MetricKind::timing) continue;
      ASSERT_EQ(a.metrics[m].value.has_value(), b.metrics[m].value.has_value()) << a.metrics[m].name;
      if (a.metrics[m].value) { EXPECT_TRUE(same_bits(*a.metrics[m].value, *b.metrics[m].value)) << a.metrics[m].name; }
    }
  }
}

TEST(TrajectoryCache, BuildsOncePerKeyUnderConcurrentUse) {
  TrajectoryCache cache;
  std::atomic<int> calls{0};
  const auto build = [&calls] {
    ++calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    JobTrajectories t;
    t.training.q = Eigen::MatrixXd::Constant(10, 3, 1.0);
    return t;
  };
  std::vector<std::thread> threads;
  std::vector<std::shared_ptr<const JobTrajectories>> got(6);
  for (int i = 0; i < 6; ++i) threads.emplace_back([&, i] { got[i] = cache.get(i % 2 ? "a" : "b", build); });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(calls.load(), 2);
  EXPECT_EQ(cache.builds(), 2);
  EXPECT_EQ(got[0].get(), got[2].get());
  EXPECT_EQ(got[1].get(), got[3].get());
  EXPECT_NE(got[0].get(), got[1].get());
}

TEST(TrajectoryCache, FailedBuildIsNotKeptAndBudgetEvictsTheOldest) {
  TrajectoryCache cache(2000);  // bytes: one 10 × 10 build (800 bytes in q) fits twice
  EXPECT_THROW(cache.get("bad", []() -> JobTrajectories { throw std::invalid_argument("trajectory: no"); }), std::invalid_argument);
  int calls = 0;
  const auto build = [&calls] {
    ++calls;
    JobTrajectories t;
    t.training.q = Eigen::MatrixXd::Zero(10, 10);
    return t;
  };
  EXPECT_EQ(cache.get("bad", build)->training.q.rows(), 10);  // rebuilt, not the stored failure
  cache.get("x", build);
  cache.get("y", build);  // over budget: "bad" (least recent) goes
  EXPECT_EQ(calls, 3);
  cache.get("y", build);
  cache.get("x", build);
  EXPECT_EQ(calls, 3);
  cache.get("bad", build);
  EXPECT_EQ(calls, 4);
}

}  // namespace
}  // namespace armfarm
