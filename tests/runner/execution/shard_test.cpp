// Balanced shards: jobs dealt by estimated cost (largest first into the least-loaded shard),
// deterministic whatever the order; an uneven experiment sweep splits within 20 % of cost; the
// experiment estimate against its closed form; reference-database calibration.
#include "runner/execution/shard.hpp"

#include "support/fake_job.hpp"
#include "runner/execution/job_cost.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <numeric>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

std::string make_key(int i) {
  char key[33];
  std::snprintf(key, sizeof key, "%016x%016x", static_cast<unsigned>(i * 2654435761u), static_cast<unsigned>(i));
  return key;
}

std::vector<double> calc_shard_costs(const std::vector<int>& shard_of, const std::vector<double>& costs, int count) {
  std::vector<double> totals(static_cast<std::size_t>(count), 0.0);
  for (std::size_t i = 0; i < shard_of.size(); ++i) totals[static_cast<std::size_t>(shard_of[i] - 1)] += costs[i];
  return totals;
}

TEST(ShardAssignment, EqualJobsSplitEvenly) {
  // The issue's case: 12 jobs in 3 shards split 7/5/0 by key hash.
  std::vector<std::string> keys;
  for (int i = 0; i < 12; ++i) keys.push_back(make_key(i));
  const std::vector<int> shard_of = calc_shard_assignment(keys, {}, 3);
  std::map<int, int> counts;
  for (int s : shard_of) ++counts[s];
  EXPECT_EQ(counts, (std::map<int, int>{{1, 4}, {2, 4}, {3, 4}}));
}

TEST(ShardAssignment, LargestFirstIntoTheLeastLoadedShard) {
  // Costs 7 5 4 3 2 1 into 2 shards: 7→1, 5→2, 4→2 (9), 3→1 (10), 2→2 (11), 1→1 (11).
  const std::vector<std::string> keys = {"a", "b", "c", "d", "e", "f"};
  const std::vector<double> costs = {7, 5, 4, 3, 2, 1};
  EXPECT_EQ(calc_shard_assignment(keys, costs, 2), (std::vector<int>{1, 2, 2, 1, 2, 1}));
  EXPECT_THROW(calc_shard_assignment(keys, {1, 2}, 2), std::invalid_argument);
  EXPECT_THROW(calc_shard_assignment(keys, {7, 5, 4, 3, 2, std::nan("")}, 2), std::invalid_argument);
}

TEST(ShardAssignment, TheDealDoesNotDependOnTheOrderOfTheJobs) {
  std::vector<std::string> keys;
  std::vector<double> costs;
  for (int i = 0; i < 40; ++i) {
    keys.push_back(make_key(i));
    costs.push_back(1.0 + (i % 7) * (i % 3));  // many equal costs: ties go by key
  }
  const std::vector<int> first = calc_shard_assignment(keys, costs, 4);
  std::map<std::string, int> by_key;
  for (std::size_t i = 0; i < keys.size(); ++i) by_key[keys[i]] = first[i];
  std::vector<std::size_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  for (int trial = 0; trial < 5; ++trial) {
    std::rotate(order.begin(), order.begin() + 7, order.end());
    std::reverse(order.begin() + trial, order.end());
    std::vector<std::string> k;
    std::vector<double> c;
    for (std::size_t i : order) {
      k.push_back(keys[i]);
      c.push_back(costs[i]);
    }
    const std::vector<int> again = calc_shard_assignment(k, c, 4);
    for (std::size_t i = 0; i < k.size(); ++i) EXPECT_EQ(again[i], by_key.at(k[i])) << k[i];
  }
}

class ExperimentShardTest : public ::testing::Test {
 protected:
  ExpandedSweep expand(const std::string& text) const {
    return expand_sweep(parse_sweep_spec(text, "test.json", std::string(ARMFARM_SOURCE_DIR) + "/sweeps", schema_), schema_);
  }
  JobConfigSchema schema_ = make_experiment_config_schema();
};

TEST_F(ExperimentShardTest, TheEstimateIsDurationTimesJointsTimesTheModeFactor) {
  const JobCostModel model;
  const JobCostFunction estimate = make_experiment_cost_function(model);
  const ExpandedSweep sweep = expand(R"({"name": "e", "base": {"model": "../models/dlr_lwr3.urdf",
      "trajectory": {"kind": "sine", "sine": {"duration": 10}}, "learning": {"heldout": false}},
      "sweep": {"zip": [{"learning.mode": ["none", "online", "batch"], "control.feed_forward": ["none", "learner", "learner"]}],
                "grid": {"active_joints": [[2], [1, 2, 4], []]}}})");
  ASSERT_EQ(sweep.jobs.size(), 9u);
  for (const ExpandedJob& job : sweep.jobs) {
    const std::string mode = job.config().at("learning").at("mode");
    const std::size_t listed = job.config().at("active_joints").size();
    const double joints = listed == 0 ? 7.0 : static_cast<double>(listed);  // [] = all 7 of the DLR LWR III
    // batch: collect_repeats (2) passes under feedback, then the control pass.
    const double expected = mode == "none"     ? 10.0 * joints * model.none_factor
                            : mode == "online" ? 10.0 * joints * model.online_factor
                                               : 3.0 * 10.0 * joints * model.batch_factor;
    const JobCostEstimate e = estimate(job.config(), job.checked.get());
    EXPECT_NEAR(e.cost, expected, 1e-9 * expected) << job.params.dump();
    EXPECT_EQ(e.kind, mode + " sine " + std::to_string(static_cast<int>(joints)) + " joints");
    // The estimate from the configuration the expansion checked is the one from the JSON read again.
    const JobCostEstimate read = estimate(job.config(), nullptr);
    EXPECT_EQ(read.cost, e.cost) << job.params.dump();
    EXPECT_EQ(read.seconds, e.seconds) << job.params.dump();
    EXPECT_EQ(read.kind, e.kind) << job.params.dump();
  }
}

TEST_F(ExperimentShardTest, AnUnevenSweepSplitsWithinTwentyPercentOfCost) {
  // Costs spread over a factor of about 70: modes × durations × joint counts, held-out passes on.
  const ExpandedSweep sweep = expand(R"({"name": "uneven", "base": {"model": "../models/dlr_lwr3.urdf",
      "trajectory": {"kind": "sine"}},
      "sweep": {"zip": [{"learning.mode": ["none", "online", "batch"], "control.feed_forward": ["none", "learner", "learner"]}],
                "grid": {"trajectory.sine.duration": [4, 9, 20], "active_joints": [[1], [1, 2, 3], []]}}})");
  ASSERT_EQ(sweep.jobs.size(), 27u);
  const std::vector<double> costs = calc_job_costs(sweep, make_experiment_cost_function());
  std::vector<std::string> keys;
  for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
  EXPECT_GT(*std::max_element(costs.begin(), costs.end()) / *std::min_element(costs.begin(), costs.end()), 50.0);
  for (int count : {2, 3, 4}) {
    const std::vector<double> totals = calc_shard_costs(calc_shard_assignment(keys, costs, count), costs, count);
    const double high = *std::max_element(totals.begin(), totals.end());
    const double low = *std::min_element(totals.begin(), totals.end());
    EXPECT_LE(high, 1.2 * low) << count << " shards: " << high << " against " << low;
  }
}

TEST(JobCosts, AReferenceDatabaseCalibratesTheEstimatesByKind) {
  const fs::path folder = fs::temp_directory_path() / ("armfarm_shard_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  const JobConfigSchema schema = make_fake_job_config_schema();
  // Two kinds: 2 joints (kp has 2 entries, the default) and 3 joints; durations 1, 2, 4 s.
  const ExpandedSweep sweep = expand_sweep(
      parse_sweep_spec(R"({"name": "cal", "sweep": {"grid": {"simulation.duration": [1, 2, 4]},
          "zip": [{"control.kp": [[100, 50], [100, 50, 20]], "control.kd": [[10, 5], [10, 5, 2]]}]}})",
                       "cal.json", ".", schema),
      schema);
  ASSERT_EQ(sweep.jobs.size(), 6u);
  const JobCostFunction estimate = make_fake_job_cost_function();
  // Reference: the 1 s jobs of both kinds done, 2-joint one in 3 s of wall time, 3-joint in 0.5 s.
  const std::string db = (folder / "reference.db").string();
  {
    ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_write);
    SweepRegistration registration;
    registration.name = "cal";
    registration.spec_text = "{}";
    registration.spec_hash = "h";
    registration.started_at = make_utc_timestamp();
    std::vector<JobRegistration> jobs;
    for (const ExpandedJob& job : sweep.jobs) jobs.push_back({job.key, job.params, job.config(), job.seed});
    store.insert_sweep_run(registration, jobs);
    JobBatch batch;
    for (const ExpandedJob& job : sweep.jobs) {
      if (job.config().at("simulation").at("duration") != 1.0) continue;
      JobResultRecord result;
      result.key = job.key;
      result.status = "done";
      result.wall_seconds = job.config().at("control").at("kp").size() == 2 ? 3.0 : 0.5;
      result.started_at = result.finished_at = make_utc_timestamp();
      batch.finished.push_back(result);
    }
    store.insert_job_batch(batch, "cal");
  }
  const ResultsStore reference = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<double> costs = calc_job_costs(sweep, estimate, &reference);
  for (std::size_t i = 0; i < sweep.jobs.size(); ++i) {
    const ExpandedJob& job = sweep.jobs[i];
    const double duration = job.config().at("simulation").at("duration");
    const bool two = job.config().at("control").at("kp").size() == 2;
    const double measured = two ? 3.0 : 0.5;
    // Done there: its own wall time. Otherwise: its estimate × (wall / estimate) of its kind's done job.
    const double expected =
        duration == 1.0 ? measured : estimate(job.config(), nullptr).cost * measured / estimate(sweep.jobs[two ? 0 : 1].config(), nullptr).cost;
    EXPECT_NEAR(costs[i], expected, 1e-12) << job.params.dump();
  }
  // Without the reference: the estimates themselves.
  const std::vector<double> raw = calc_job_costs(sweep, estimate);
  for (std::size_t i = 0; i < sweep.jobs.size(); ++i) EXPECT_EQ(raw[i], estimate(sweep.jobs[i].config(), nullptr).cost);
  fs::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
