// A job runs only on the bytes its key names: when a model or a recorded trajectory changes
// between the expansion (which hashed it into the key) and the job's run, the job refuses to
// run instead of storing results under a key that names other bytes.
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class InputHashCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("input_hash");
    fs::copy_file(fs::path(ARMFARM_SOURCE_DIR) / "models" / "planar2.urdf", dir_ / "arm.urdf");
    std::ofstream csv(dir_ / "motion.csv");
    csv << "q1,q2\n";  // 1 s at 100 Hz, a slow swing of both joints
    for (int row = 0; row < 100; ++row) csv << 0.2 * std::sin(0.05 * row) << "," << 0.1 * std::sin(0.03 * row) << "\n";
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
      const JobOutcome outcome = make_experiment_executor()(config, JobControl{});
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
