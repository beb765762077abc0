// The experiment job's schema check and executor (runner/execution/experiment_executor.cpp): the
// check at the expansion makes the job's validated configuration, which the job carries to the
// executor (ExpandedJob::checked) instead of being parsed and validated again there.
#include "runner/execution/checked_experiment_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "support/recorded_arm.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class ExperimentExecutorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("experiment_executor");
    test_support::write_recorded_planar_arm(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  ExpandedSweep expand(const std::string& text) {
    const fs::path spec = dir_ / "spec.json";
    std::ofstream(spec) << text;
    return expand_sweep(load_sweep_spec(spec.string(), schema_), schema_);
  }

  // The spec of one recorded job on the scratch arm, with a grid of `init_D` values.
  static std::string make_recorded_spec(const std::string& init_D) {
    return R"({"name": "carried", "base": {"model": "arm.urdf",
        "trajectory": {"kind": "recorded", "recorded": {"file": "motion.csv", "task_space": false}}},
        "sweep": {"grid": {"learning.lwpr.init_D": )" + init_D + "}}}";
  }

  JobConfigSchema schema_ = make_experiment_config_schema();
  fs::path dir_;
};

TEST_F(ExperimentExecutorTest, AnExpandedJobCarriesTheConfigurationItsCheckValidated) {
  const ExpandedSweep sweep = expand(make_recorded_spec("[0.5, 2.5]"));
  ASSERT_EQ(sweep.jobs.size(), 2u);
  for (const ExpandedJob& job : sweep.jobs) {
    const CheckedExperimentJob* checked = find_checked_experiment_job(job.checked.get());
    ASSERT_NE(checked, nullptr) << job.params.dump();
    // The axis's value, the recorded samples as read, and the model file the inputs record.
    const JobConfig& config = checked->job.get();
    EXPECT_EQ(config.learning.lwpr.init_D(0, 0), job.params.at("learning.lwpr.init_D").get<double>());
    EXPECT_EQ(config.trajectory.recorded.samples.rows(), 100);
    EXPECT_EQ(config.trajectory.recorded.samples.cols(), 2);
    EXPECT_EQ(checked->model_path, job.config().at("inputs").at("model").at("resolved").get<std::string>());
  }
  EXPECT_NE(sweep.jobs[0].checked, sweep.jobs[1].checked);
}

TEST_F(ExperimentExecutorTest, ACarriedJobRunsOnTheBytesItsExpansionRead) {
  // The executor reads nothing of the carried configuration again: a recorded trajectory changed
  // after the expansion does not reach the job (it runs on the bytes its key names), while the
  // same JSON without what the check made of it is read now and refused.
  const ExpandedSweep sweep = expand(make_recorded_spec("[0.5]"));
  ASSERT_EQ(sweep.jobs.size(), 1u);
  const ExpandedJob& job = sweep.jobs[0];
  std::ofstream(dir_ / "motion.csv", std::ios::app) << "0.2,0.1\n";  // one row more
  const JobExecutor executor = make_experiment_executor();
  const JobOutcome carried = executor(job.config(), job.checked.get(), JobControl{});
  EXPECT_EQ(carried.status, JobStatus::done) << carried.message;
  try {
    executor(job.config(), nullptr, JobControl{});
    ADD_FAILURE() << "the changed recorded trajectory was not refused";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.json_path(), "trajectory.recorded.file");
    EXPECT_NE(error.message().find("changed since the sweep was expanded"), std::string::npos) << error.what();
  }
}

TEST_F(ExperimentExecutorTest, TheModelFileIsStillCheckedAgainstItsKey) {
  // The model is loaded when the job runs, so its bytes are compared with the key's even when the
  // configuration comes carried.
  const ExpandedSweep sweep = expand(make_recorded_spec("[0.5]"));
  ASSERT_EQ(sweep.jobs.size(), 1u);
  std::ofstream(dir_ / "arm.urdf", std::ios::app) << "<!-- edited after the expansion -->\n";
  try {
    make_experiment_executor()(sweep.jobs[0].config(), sweep.jobs[0].checked.get(), JobControl{});
    ADD_FAILURE() << "the changed model was not refused";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.json_path(), "model");
    EXPECT_NE(error.message().find("changed since the sweep was expanded"), std::string::npos) << error.what();
  }
}

TEST_F(ExperimentExecutorTest, AnotherKindsCheckIsRefused) {
  struct OtherKind : CheckedConfig {};
  const OtherKind other;
  EXPECT_EQ(find_checked_experiment_job(nullptr), nullptr);
  EXPECT_THROW(find_checked_experiment_job(&other), std::logic_error);
}

}  // namespace
}  // namespace armfarm
