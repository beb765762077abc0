// The end effector of a job on a file with several leaf links: refused with both names and
// how to choose, accepted with `--ee` and with `end_effector.link` in the configuration (the
// same job key either way), and the choice is part of the key.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace {

CommandResult run_job(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_BINARY) + " job " + arguments;
  return run_command_line(command);
}

class CmdJobEndEffector : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("armfarm_job_ee_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // A short feedback-only sine on two_leaves.urdf, plus `extra` keys.
  std::string write_config(const std::string& name, const std::string& extra) const {
    const std::string path = (folder_ / (name + ".json")).string();
    std::ofstream(path) << R"({"model": ")" << ARMFARM_TEST_DATA_DIR << R"(/models/two_leaves.urdf",
      "trajectory": {"sine": {"duration": 0.5}}, "control": {"mode": "feedback", "feed_forward": "none"},
      "learning": {"mode": "none"})" << extra << "}";
    return path;
  }

  std::filesystem::path folder_;
};

TEST_F(CmdJobEndEffector, SeveralLeavesAreRefusedListingThem) {
  const std::string path = write_config("plain", "");
  const CommandResult result = run_job(path);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(path + ": end_effector.link: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("2 leaf links ('tool0', 'camera_link'): set end_effector.link"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("--ee LINK[:x,y,z]"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

TEST_F(CmdJobEndEffector, ChosenOnTheCommandLineOrInTheConfigurationRuns) {
  const CommandResult by_option = run_job(write_config("plain", "") + " --ee tool0 --json");
  ASSERT_EQ(by_option.exit_code, 0) << by_option.output;
  const nlohmann::json a = nlohmann::json::parse(by_option.output);
  EXPECT_EQ(a["status"], "done");

  const CommandResult by_config = run_job(write_config("config", R"(, "end_effector": {"link": "tool0"})") + " --json");
  ASSERT_EQ(by_config.exit_code, 0) << by_config.output;
  const nlohmann::json b = nlohmann::json::parse(by_config.output);
  EXPECT_EQ(b["status"], "done");
  EXPECT_EQ(a["key"], b["key"]);  // the same configuration either way

  const CommandResult camera = run_job(write_config("camera", "") + " --ee camera_link:0,0,0.01 --json");
  ASSERT_EQ(camera.exit_code, 0) << camera.output;
  EXPECT_NE(nlohmann::json::parse(camera.output)["key"], a["key"]);  // the choice is in the key
}

TEST_F(CmdJobEndEffector, BadChoicesAreOneLine) {
  const CommandResult unknown = run_job(write_config("unknown", R"(, "end_effector": {"link": "tool"})"));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("end_effector.link: "), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("no link 'tool' (leaf links: 'tool0', 'camera_link')"), std::string::npos) << unknown.output;

  const CommandResult offset_alone = run_job(write_config("offset", R"(, "end_effector": {"offset": [0, 0, 0.1]})"));
  EXPECT_EQ(offset_alone.exit_code, 2) << offset_alone.output;
  EXPECT_NE(offset_alone.output.find("end_effector.offset: an offset needs end_effector.link"), std::string::npos)
      << offset_alone.output;

  const CommandResult bad_text = run_job(write_config("text", "") + " --ee tool0:1,2");
  EXPECT_EQ(bad_text.exit_code, 2) << bad_text.output;
  EXPECT_NE(bad_text.output.find("--ee 'tool0:1,2': the offset needs three numbers"), std::string::npos) << bad_text.output;
}

}  // namespace
