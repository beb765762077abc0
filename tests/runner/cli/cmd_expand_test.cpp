// `expand` and `run` of the experiment job refuse a configuration that validate() refuses for
// any job of the sweep, naming the spec file and the JSON path, before a database exists.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace {

namespace fs = std::filesystem;

CommandResult run_armfarm(const std::string& arguments) {
  // The experiment job (no ARMFARM_FAKE_JOBS), from the source tree so the model path resolves.
  const std::string command =
      "cd " + std::string(ARMFARM_SOURCE_DIR) + " && env -u ARMFARM_FAKE_JOBS " + ARMFARM_BINARY + " " + arguments;
  return run_command_line(command);
}

fs::path make_dir() {
  // One folder per test and process: ctest runs the tests of this file in parallel.
  const fs::path dir = fs::temp_directory_path() / ("armfarm_cmd_config_validation" + std::string("-") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const char* kNegativeScale = R"({"name": "bad_scale", "base": {"trajectory": {"kind": "figure_eight"}},
  "sweep": {"grid": {"trajectory.figure_eight.scale": [1.0, -1.0]}}})";

TEST(CmdConfigValidation, ExpandRefusesANegativeFigureEightScaleWithItsPath) {
  const fs::path spec = make_dir() / "bad_scale.json";
  std::ofstream(spec) << kNegativeScale;
  const CommandResult result = run_armfarm("expand " + spec.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(spec.string() + ": sweep.grid[\"trajectory.figure_eight.scale\"][1]: "
                                               "trajectory.figure_eight.scale: -1 is outside the allowed range (0, 10]"),
            std::string::npos)
      << result.output;
}

TEST(CmdConfigValidation, RunRefusesItBeforeCreatingTheDatabase) {
  const fs::path dir = make_dir();
  const fs::path spec = dir / "bad_scale.json";
  const fs::path db = dir / "results.db";
  std::ofstream(spec) << kNegativeScale;
  const CommandResult result = run_armfarm("run " + spec.string() + " --db " + db.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("trajectory.figure_eight.scale: -1 is outside the allowed range (0, 10]"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(db));
}

TEST(CmdConfigValidation, SineFrequencyAndDurationRefusedByExpand) {
  const fs::path spec = make_dir() / "bad_sine.json";
  std::ofstream(spec) << R"({"name": "bad_sine", "base": {"trajectory": {"sine": {"frequency": [-1], "duration": 1e300}}}})";
  const CommandResult result = run_armfarm("expand " + spec.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("trajectory.sine.frequency[0]: -1 Hz is outside the allowed range (0, 10] Hz"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("trajectory.sine.duration: 1e+300 s is outside"), std::string::npos) << result.output;
}

// A sine beyond a joint's velocity limit is refused at expand, naming the joint (1-based), the
// velocity it needs and the limit (the LWR III's joint 4: 1.9635 rad/s), per swept value.
TEST(CmdConfigValidation, ExpandRefusesASineBeyondAJointsVelocityLimitNamingTheJoint) {
  const fs::path spec = make_dir() / "fast_sine.json";
  std::ofstream(spec) << R"({"name": "fast_sine", "base": {"trajectory": {"sine": {"amplitude": [0.3]}}},
    "sweep": {"grid": {"trajectory.sine.frequency": [[0.25], [0.25, 0.25, 0.25, 1.5, 0.25, 0.25, 0.25]]}}})";
  const CommandResult result = run_armfarm("expand " + spec.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(spec.string() + ": sweep.grid[\"trajectory.sine.frequency\"][1]: trajectory.sine.frequency: "
                                               "joint 4 needs 2.82743 rad/s (amplitude 0.3 rad × 2π × 1.5 Hz), above its velocity "
                                               "limit 1.9635 rad/s"),
            std::string::npos)
      << result.output;
}

// An explicit PD period the step-stability criterion calls unstable is refused at expand with
// the key, the numbers and a value that works (appendix D's gains on the LWR III's wrist).
TEST(CmdConfigValidation, ExpandRefusesUnstableExplicitStepsWithTheFix) {
  const fs::path spec = make_dir() / "unstable_steps.json";
  std::ofstream(spec) << R"({"name": "unstable_steps", "base": {"control": {"gain_set": "appendix_d"}},
    "sweep": {"grid": {"pd_substeps": ["auto", 1]}}})";
  const CommandResult result = run_armfarm("expand " + spec.string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("sweep.grid[\"pd_substeps\"][1]: pd_substeps: 1 is unstable: the sampled PD loop is unstable on joint"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("is stable with the criterion's margin (or \"auto\")"), std::string::npos) << result.output;
}

}  // namespace
