// A sweep's check reads a recorded trajectory once (JobFileContents, keyed by the content hash
// the configuration records), not once a job; a configuration that records another content,
// or none, reads its file.
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/input_files.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

TEST(JobFileContents, ARecordedTrajectoryIsReadOncePerContent) {
  const fs::path dir = fs::temp_directory_path() / ("armfarm_job_file_contents_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path csv = dir / "picking.csv";
  fs::copy_file(fs::path(ARMFARM_SOURCE_DIR) / "sweeps/thesis/data/picking_synthetic.csv", csv);

  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {1, 2, 4};
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = "picking.csv";
  config["trajectory"]["recorded"]["task_space"] = true;
  config["trajectory"]["recorded"]["sample_rate"] = 100;
  InputFileReader reader;
  const JobConfigSchema schema = make_experiment_config_schema();
  auto folder_of = [&](const std::string& field) { return field == "model" ? std::string(ARMFARM_SOURCE_DIR) : dir.string(); };
  ASSERT_TRUE(record_input_files(config, schema.input_files, folder_of, reader).empty());
  ASSERT_TRUE(config["inputs"].contains("trajectory.recorded.file"));
  const ModelFacts facts{7, {}, {}};

  JobFileContents contents;
  const JobConfig first = parse_recorded_job_config(config, facts, {}, &contents);
  ASSERT_GT(first.trajectory.recorded.samples.rows(), 10);
  EXPECT_EQ(contents.recorded_hash, config["inputs"]["trajectory.recorded.file"]["hash"]);

  // The file is gone: the same content is served from what the first job read...
  fs::remove(csv);
  const JobConfig second = parse_recorded_job_config(config, facts, {}, &contents);
  EXPECT_EQ(second.trajectory.recorded.samples, first.trajectory.recorded.samples);
  EXPECT_EQ(second.trajectory.recorded.sample_lines, first.trajectory.recorded.sample_lines);
  // ...but another recorded content, and a check without the contents, read the file.
  nlohmann::json other = config;
  other["inputs"]["trajectory.recorded.file"]["hash"] = "00000000000000000000000000000000";
  EXPECT_THROW(parse_recorded_job_config(other, facts, {}, &contents), ConfigError);
  EXPECT_THROW(parse_recorded_job_config(config, facts, {}, nullptr), ConfigError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace armfarm
