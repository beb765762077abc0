// `armfarm job`: runs one configuration, prints JSON metrics; bad files give one line and exit 2.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

struct CommandResult {
  int exit_code;
  std::string output;
};

CommandResult run_job(const std::string& arguments) {
  const std::string command = "cd " + std::string(ARMFARM_SOURCE_DIR) + " && " + ARMFARM_BINARY + " job " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  return {WEXITSTATUS(pclose(pipe)), output};
}

std::string write_config(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("armfarm_cmd_job_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(CmdJob, PrintsStatusMetricsAndOneObjectPerActiveJoint) {
  const std::string path = write_config(
      "ok", R"({"active_joints": [2, 4], "trajectory": {"sine": {"duration": 2.0}}, "control": {"gain_scale": 0.2}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_EQ(out["status"], "done");
  EXPECT_GT(out["metrics"]["n_receptive_fields"].get<double>(), 0.0);
  ASSERT_EQ(out["per_joint"].size(), 2u);
  EXPECT_EQ(out["per_joint"][0]["joint"], 2);
  EXPECT_EQ(out["per_joint"][1]["joint"], 4);
  EXPECT_TRUE(out["per_joint"][1].contains("ff_fb_ratio_avg"));
}

TEST(CmdJob, DivergedJobExitsOne) {
  const std::string path = write_config(
      "diverge", R"({"trajectory": {"sine": {"duration": 2.0}}, "control": {"mode": "feedback", "feed_forward": "none",
                    "kp": [1e5], "kd": [1e4], "limit_torque": false}, "learning": {"mode": "none"}})");
  const CommandResult result = run_job(path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("status diverged"), std::string::npos) << result.output;
}

TEST(CmdJob, BadConfigurationIsOneLineNamingFileAndPath) {
  const std::string path = write_config("bad", R"({"control": {"gain_scal": 0.2}})");
  const CommandResult result = run_job(path);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find(path + ": control.gain_scal: unknown key"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

}  // namespace
