// Expansion hashes each job's key from a cut-up canonical text (JobKeyTemplate) instead of
// serializing the whole configuration: the keys must be exactly calc_job_key of the rebuilt
// configuration, for every kind of axis and for inputs that differ between jobs; and what a
// sweep keeps per job stays compact (issue 16: under 2 KB a job).
#include "support/fake_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/job_key_template.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include "support/expansion_heap.hpp"
#include "support/scratch_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

const std::string kRecording = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/data/picking_synthetic.csv";

void expect_keys_are_the_configurations(const ExpandedSweep& sweep) {
  std::set<std::string> keys;
  for (const ExpandedJob& job : sweep.jobs) {
    EXPECT_EQ(job.key, calc_job_key(job.config())) << job.params.dump();
    keys.insert(job.key);
  }
  EXPECT_EQ(keys.size(), sweep.jobs.size());
}

class JobKeyTemplateSweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("key_template");
  }
  void TearDown() override { fs::remove_all(dir_); }

  ExpandedSweep expand(const std::string& text) {
    const std::string path = (dir_ / "spec.json").string();
    std::ofstream(path) << text;
    const JobConfigSchema schema = make_experiment_config_schema();
    return expand_sweep(load_sweep_spec(path, schema), schema);
  }

  fs::path dir_;
};

TEST_F(JobKeyTemplateSweep, GridZipRandomRepeatAndIncludesGiveTheConfigurationsKeys) {
  std::ofstream(dir_ / "common.json") << R"({"control": {"gain_scale": 0.5, "kp": [300, 300, 200, 200, 100, 100, 50]}})";
  const ExpandedSweep sweep = expand(R"({"name": "k", "include": ["common.json"],
      "sweep": {"grid": {"control.gain_scale": [0.2, 1], "control.kp[1]": [40, 60]},
                "zip": [{"learning.lwpr.init_D": [20, 50], "learning.lwpr.init_alpha": [100, 250]}],
                "random": {"samples": 2, "seed": 3, "params": {"learning.lwpr.w_gen": {"uniform": [0.1, 0.3]},
                                                               "trajectory.kind": {"choice": ["sine", "figure_eight"]}}},
                "repeat": 2}})");
  ASSERT_EQ(sweep.jobs.size(), 2u * 2u * 2u * 2u * 2u);
  expect_keys_are_the_configurations(sweep);
  for (const ExpandedJob& job : sweep.jobs) ASSERT_TRUE(job.config()["inputs"].contains("include[0]"));
}

TEST_F(JobKeyTemplateSweep, InputsThatDifferBetweenJobsGiveTheConfigurationsKeys) {
  // The recording is an input only where trajectory.kind is "recorded": two kinds of "inputs".
  const ExpandedSweep by_kind = expand(R"({"name": "k", "base": {"active_joints": [1, 2, 4],
      "trajectory": {"recorded": {"file": ")" + kRecording + R"(", "task_space": true, "sample_rate": 100}}},
      "sweep": {"grid": {"trajectory.kind": ["sine", "recorded"], "control.gain_scale": [0.2, 1]}}})");
  ASSERT_EQ(by_kind.jobs.size(), 4u);
  expect_keys_are_the_configurations(by_kind);
  EXPECT_FALSE(by_kind.jobs[0].config()["inputs"].contains("trajectory.recorded.file"));
  EXPECT_TRUE(by_kind.jobs[3].config()["inputs"].contains("trajectory.recorded.file"));

  // An axis over an input file itself: the key hashes the file's content at that element.
  const ExpandedSweep by_file = expand(R"({"name": "k", "base": {"active_joints": [1, 2, 4],
      "trajectory": {"kind": "recorded", "recorded": {"task_space": true, "sample_rate": 100}}},
      "sweep": {"grid": {"trajectory.recorded.file": [")" + kRecording + R"(", ")" + kRecording + R"("],
                         "control.gain_scale": [0.2, 1]}}})");
  ASSERT_EQ(by_file.jobs.size(), 2u);  // the same file twice: the same jobs, kept once
  expect_keys_are_the_configurations(by_file);
}

TEST_F(JobKeyTemplateSweep, BadValuesAreStillReportedWithTheirPath) {
  try {
    expand(R"({"name": "k", "sweep": {"grid": {"control.gain_scale": [0.2, -1], "learning.lwpr.init_alpha": [1, 2]}}})");
    FAIL() << "a negative gain scale expanded";
  } catch (const SpecError& error) {
    ASSERT_EQ(error.lines().size(), 1u);
    EXPECT_NE(error.lines()[0].find("spec.json: sweep.grid[\"control.gain_scale\"][1]: control.gain_scale:"),
              std::string::npos)
        << error.lines()[0];
  }
}

TEST(JobKeyTemplate, KeysMatchCalcJobKeyAndInputFieldsAreNotHoles) {
  const nlohmann::json config = {
      {"seed", 3},
      {"model", "arm.urdf"},
      {"control", {{"gain_scale", 1.0}, {"kp", {1.0, 2.5, 3.0}}}},
      {"inputs", {{"model", {{"path", "arm.urdf"}, {"resolved", "/m/arm.urdf"}, {"hash", "ab"}, {"files", nlohmann::json::array()}}}}}};
  const std::vector<ConfigPath> holes = {parse_config_path("control.kp[1]"), parse_config_path("seed")};
  const JobKeyTemplate key_template(config, holes);
  ASSERT_TRUE(key_template.usable());
  std::string scratch;
  for (const nlohmann::json& kp : {nlohmann::json(7.25), nlohmann::json("x\"y"), nlohmann::json({{"b", 1}, {"a", 2.0}})}) {
    nlohmann::json job = config;
    set_config_element(job, holes[0], kp);
    set_config_element(job, holes[1], 11);
    const std::string kp_text = calc_canonical_json(kp), seed_text = calc_canonical_json(11);
    EXPECT_EQ(key_template.calc_key({&kp_text, &seed_text}, scratch), calc_job_key(job)) << kp.dump();
  }
  // The key document rewrites input fields and "inputs": those cannot vary in the cut-up text.
  EXPECT_FALSE(JobKeyTemplate(config, {parse_config_path("model")}).usable());
  EXPECT_FALSE(JobKeyTemplate(config, {parse_config_path("inputs.model.hash")}).usable());
  EXPECT_FALSE(JobKeyTemplate(config, {parse_config_path("control"), parse_config_path("control.gain_scale")}).usable());
  EXPECT_FALSE(JobKeyTemplate(config, {parse_config_path("control.kd")}).usable());  // names nothing
}

TEST(BoundedExpansionMemory, ASweepKeepsUnderTwoKilobytesPerJob) {
#if defined(__SANITIZE_ADDRESS__) || !defined(__GLIBC__)
  GTEST_SKIP() << "heap in use is measured with glibc's mallinfo2, which sanitizers replace";
#else
  // 10^4 fake jobs: the heap the sweep holds after expansion (what a 10^5 sweep holds, tenfold).
  std::string first, second;
  for (int i = 0; i < 100; ++i) first += (i ? "," : "") + std::to_string(0.5 + 0.001 * i);
  for (int i = 0; i < 100; ++i) second += (i ? "," : "") + std::to_string(1.0 + 0.01 * i);
  const std::string text = R"({"name": "m", "sweep": {"grid": {"control.gain_scale": [)" + first +
                           R"(], "trajectory.period": [)" + second + "]}}}";
  const test_support::MeasuredExpansion measured =
      test_support::expand_measuring_heap(text, make_fake_job_config_schema());
  const ExpandedSweep& sweep = measured.sweep;
  ASSERT_EQ(sweep.jobs.size(), 10000u);
  const double per_job = measured.bytes_per_job;
  EXPECT_LT(per_job, 2048.0);
  RecordProperty("bytes_per_job", std::to_string(per_job));
  for (const ExpandedJob& job : sweep.jobs) {
    ASSERT_EQ(job.base.get(), sweep.jobs.front().base.get());
    ASSERT_FALSE(job.full);
    ASSERT_EQ(job.params.size(), 2u);
  }
#endif
}

}  // namespace
}  // namespace armfarm
