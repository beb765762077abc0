// find_input_changes: a job whose key the database lacks is "new because an input changed" only
// when the sweep's stored jobs hold one with the same params and the same configuration apart
// from its input files, including jobs stored before inputs were recorded.
#include "runner/execution/input_changes.hpp"

#include "results/results_store.hpp"
#include "runner/spec/canonical_json.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

nlohmann::json make_config(double gain, const std::string& model_hash) {
  nlohmann::json config = {{"model", "models/arm.urdf"}, {"control", {{"gain_scale", gain}}}};
  if (!model_hash.empty()) {
    config["inputs"]["model"] = {{"path", "models/arm.urdf"}, {"resolved", "/x/models/arm.urdf"}, {"hash", model_hash}};
  }
  return config;
}

ExpandedJob make_job(double gain, const std::string& model_hash) {
  ExpandedJob job = ExpandedJob::from_config(make_config(gain, model_hash));
  job.params = {{"control.gain_scale", gain}};  // the value the configuration already has
  return job;
}

class InputChangesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = (fs::temp_directory_path() / ("armfarm_input_changes_" + std::to_string(getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db"))
              .string();
    fs::remove(db_);
  }
  void TearDown() override { fs::remove(db_); }

  void store(const std::vector<ExpandedJob>& jobs) {
    ResultsStore store = ResultsStore::open(db_, ResultsStore::Mode::read_write);
    SweepRegistration sweep;
    sweep.name = "s";
    sweep.started_at = make_utc_timestamp();
    std::vector<JobRegistration> registrations;
    for (const ExpandedJob& job : jobs) registrations.push_back({job.key, job.params, job.config(), 0});
    store.insert_sweep_run(sweep, registrations);
  }

  std::string db_;
};

TEST_F(InputChangesTest, CountsJobsWhoseOnlyDifferenceIsAnInputHash) {
  store({make_job(0.5, "aaaa"), make_job(1.0, "aaaa")});
  ExpandedSweep sweep;
  sweep.spec.name = "s";
  sweep.jobs = {make_job(0.5, "bbbb"), make_job(1.0, "aaaa"), make_job(2.0, "bbbb")};
  const InputChangeReport report = find_input_changes(sweep, db_);
  EXPECT_EQ(report.changed, 1);  // 1.0 is stored as is; 2.0 is a new parameter value
  EXPECT_EQ(report.inputs, (std::map<std::string, int>{{"model", 1}}));
  EXPECT_EQ(make_input_change_text(report), "1 job is new because an input file changed (model: 1)");
}

TEST_F(InputChangesTest, JobsStoredBeforeInputsWereRecordedCount) {
  store({make_job(0.5, ""), make_job(1.0, "")});
  ExpandedSweep sweep;
  sweep.spec.name = "s";
  sweep.jobs = {make_job(0.5, "bbbb"), make_job(1.0, "bbbb")};
  EXPECT_EQ(find_input_changes(sweep, db_).changed, 2);
}

TEST_F(InputChangesTest, OtherChangesAndMissingDatabasesAreNotInputChanges) {
  ExpandedSweep sweep;
  sweep.spec.name = "s";
  sweep.jobs = {make_job(0.5, "bbbb")};
  EXPECT_EQ(find_input_changes(sweep, db_).changed, 0);  // no database yet
  EXPECT_FALSE(fs::exists(db_));                          // and none created
  nlohmann::json changed = make_config(0.5, "aaaa");
  changed["control"]["limit_torque"] = false;  // a configuration change, same params
  ExpandedJob other = ExpandedJob::from_config(changed);
  other.params = {{"control.gain_scale", 0.5}};
  store({other});
  EXPECT_EQ(find_input_changes(sweep, db_).changed, 0);
  EXPECT_EQ(make_input_change_text(find_input_changes(sweep, db_)), "");
}

}  // namespace
}  // namespace armfarm
