// find_input_changes: a job whose key the database lacks is "new because an input changed" only
// when the sweep's stored jobs hold one with the same params and the same configuration apart
// from its input files, including jobs stored before inputs were recorded.
#include "runner/execution/input_changes.hpp"

#include "results/results_store.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "support/recorded_arm.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <cmath>
#include <fstream>
#include <string>

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

// ------------------------------------------------------------------------------------------------
// Folded in from runner/execution/input_hash_check_test.cpp:
// A job runs only on the bytes its key names: when a model or a recorded trajectory changes
// between the expansion (which hashed it into the key) and the job's run, the job refuses to
// run instead of storing results under a key that names other bytes.

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class InputHashCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("input_hash");
    test_support::write_recorded_planar_arm(dir_);
    std::ofstream(dir_ / "spec.json") << R"({"name": "hashes", "base": {"model": "arm.urdf",
        "trajectory": {"kind": "recorded", "recorded": {"file": "motion.csv", "task_space": false}}}})";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The one job of spec.json, as expanded now (its inputs hashed into its configuration).
  nlohmann::json expand_job() {
    const JobConfigSchema schema = make_experiment_config_schema();
    const ExpandedSweep sweep = expand_sweep(load_sweep_spec((dir_ / "spec.json").string(), schema), schema);
    EXPECT_EQ(sweep.jobs.size(), 1u);
    return sweep.jobs.at(0).config();
  }

  // The ConfigError of running `config` ("(ran: STATUS)" when it runs).
  static std::string run_error(const nlohmann::json& config) {
    try {
      const JobOutcome outcome = make_experiment_executor()(config, nullptr, JobControl{});
      return "(ran: " + std::string(outcome.status == JobStatus::done ? "done" : "not done") + ")";
    } catch (const ConfigError& error) {
      return error.what();
    }
  }

  fs::path dir_;
};

TEST_F(InputHashCheck, UnchangedInputsRun) { EXPECT_EQ(run_error(expand_job()), "(ran: done)"); }

TEST_F(InputHashCheck, ARecordedTrajectoryChangedAfterTheExpansionIsRefused) {
  const nlohmann::json job = expand_job();
  std::ofstream(dir_ / "motion.csv", std::ios::app) << "0.2,0.1\n";  // one row more
  const std::string error = run_error(job);
  const std::string file = (dir_ / "motion.csv").lexically_normal().string();
  EXPECT_EQ(error.rfind("trajectory.recorded.file: " + file + ": changed since the sweep was expanded (content hash ", 0), 0u)
      << error;
  EXPECT_NE(error.find("run the sweep again and the job gets a new key)"), std::string::npos) << error;
  // Expanded anew, the job has the new bytes' key and runs.
  const nlohmann::json again = expand_job();
  EXPECT_NE(again.at("inputs").at("trajectory.recorded.file").at("hash"), job.at("inputs").at("trajectory.recorded.file").at("hash"));
  EXPECT_EQ(run_error(again), "(ran: done)");
}

TEST_F(InputHashCheck, AModelChangedAfterTheExpansionIsRefused) {
  const nlohmann::json job = expand_job();
  std::ofstream(dir_ / "arm.urdf", std::ios::app) << "<!-- edited after the expansion -->\n";
  const std::string error = run_error(job);
  const std::string file = (dir_ / "arm.urdf").lexically_normal().string();
  EXPECT_EQ(error.rfind("model: " + file + ": changed since the sweep was expanded (content hash ", 0), 0u) << error;
}

TEST_F(InputHashCheck, AnInitialModelFileChangedAfterTheExpansionIsRefusedBeforeItIsRead) {
  // The hash check comes before the bytes are decoded, so any bytes show it.
  nlohmann::json job = expand_job();
  const std::string file = (dir_ / "start.lwpr").string();
  std::ofstream(file, std::ios::binary) << "the bytes read now";
  job["learning"]["initial_model"] = file;
  job["inputs"]["learning.initial_model"] = {{"path", file}, {"resolved", file}, {"hash", calc_text_hash("the bytes hashed then")}};
  std::string error = "(accepted)";
  try {
    parse_recorded_job_config(job, ModelFacts{2, {}, {}});
  } catch (const ConfigError& e) {
    error = e.what();
  }
  EXPECT_EQ(error.rfind("learning.initial_model: " + file + ": changed since the sweep was expanded (content hash ", 0), 0u)
      << error;
}

}  // namespace
}  // namespace armfarm
