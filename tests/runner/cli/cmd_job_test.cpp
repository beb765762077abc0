// `armfarm job`: runs one configuration, prints JSON metrics; bad files give one line and exit 2.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace {

CommandResult run_job(const std::string& arguments) {
  const std::string command = "cd " + std::string(ARMFARM_SOURCE_DIR) + " && " + ARMFARM_BINARY + " job " + arguments;
  return run_command_line(command);
}

std::string write_config(const std::string& name, const std::string& text) {
  const std::string path = armfarm::test_support::scratch_file("cmd_job_" + name + ".json");
  std::ofstream(path) << text;
  return path;
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

TEST(CmdJob, EveryNullHasAReasonBesideIt) {
  // Joint 7 holds still: its nMSE is undefined (null) and the job-level mean leaves it out.
  const std::string path = write_config("null", R"({"trajectory": {"sine": {"duration": 2.0,
      "amplitude": [0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.0], "frequency": [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]}},
      "control": {"mode": "feedback", "feed_forward": "none"}, "learning": {"mode": "none"}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  int nulls = 0;
  const auto check = [&](const nlohmann::json& values, const nlohmann::json& reasons, const std::string& where) {
    for (const auto& [name, value] : values.items()) {
      if (!value.is_null()) continue;
      ++nulls;
      ASSERT_TRUE(reasons.is_object() && reasons.contains(name)) << where << " " << name << " is null without a reason";
      EXPECT_FALSE(reasons.at(name).get<std::string>().empty()) << where << " " << name;
    }
  };
  check(out["metrics"], out["reasons"], "metrics");
  for (const nlohmann::json& joint : out["per_joint"]) {
    check(joint, joint.value("reasons", nlohmann::json()), "joint " + joint["joint"].dump());
  }
  EXPECT_GE(nulls, 1);
  const nlohmann::json& seventh = out["per_joint"][6];
  ASSERT_EQ(seventh["joint"], 7);
  EXPECT_TRUE(seventh["tracking_nmse"].is_null());
  EXPECT_NE(seventh["reasons"]["tracking_nmse"].get<std::string>().find("nMSE floor"), std::string::npos) << seventh;
  // The mean is defined and says what it left out.
  EXPECT_TRUE(out["metrics"]["tracking_nmse"].is_number());
  EXPECT_NE(out["reasons"].value("tracking_nmse", "").find("7"), std::string::npos) << out["reasons"];
}

TEST(CmdJob, CheckpointsAreSpelledAsTheSweepViewSpellsThem) {
  const std::string path = write_config("checkpoints", R"({"trajectory": {"kind": "reaching",
      "reaching": {"reaches": 2, "points_per_reach": 50}}, "control": {"gain_scale": 0.2},
      "learning": {"mode": "online", "heldout_segments": 2, "heldout_checkpoints": [0, 2]}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_TRUE(out["metrics"].contains("heldout_test_nmse_c0")) << out["metrics"];
  EXPECT_TRUE(out["metrics"].contains("heldout_test_nmse_c2")) << out["metrics"];
  for (const auto& [name, value] : out["metrics"].items()) EXPECT_EQ(name.find('@'), std::string::npos) << name;
}

TEST(CmdJob, DivergedJobExitsOne) {
  const std::string path = write_config(
      "diverge", R"({"trajectory": {"sine": {"duration": 2.0}}, "control": {"mode": "feedback", "feed_forward": "none",
                    "gain_scale": 0.003}, "learning": {"mode": "none"}})");
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

TEST(CmdJob, NonsenseValuesAreRefusedBeforeTheJobStarts) {
  // Each of these used to run: dt 1e-300 ended done with NULL metrics, duration 1e300 overflowed
  // the tick count, integrator_accuracy 1e-300 hung.
  const std::pair<const char*, const char*> cases[] = {
      {R"({"dt": 1e-300})", "dt: 1e-300 s is outside the allowed range [0.0001, 0.1] s"},
      {R"({"trajectory": {"sine": {"duration": 1e300}}})", "trajectory.sine.duration: 1e+300 s is outside the allowed range"},
      {R"({"integrator_accuracy": 1e-300})", "integrator_accuracy: 1e-300 is outside the allowed range [1e-12, 0.1]"},
      {R"({"trajectory": {"sine": {"duration": 60000}}})", "trajectory.sine.duration: the job would take 6.0008e+06 control ticks"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string path = write_config("nonsense", text);
    const CommandResult result = run_job(path);
    EXPECT_EQ(result.exit_code, 2) << text << "\n" << result.output;
    EXPECT_NE(result.output.find(path + ": " + expected), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  }
}

TEST(CmdJob, WallTimeLimitStopsTheJob) {
  const std::string path = write_config("slow", R"({"trajectory": {"sine": {"duration": 600.0}}})");
  const auto start = std::chrono::steady_clock::now();
  const CommandResult result = run_job(path + " --timeout 0.3 --json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(result.exit_code, 1) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_EQ(out["status"], "timeout");
  EXPECT_EQ(out["message"], "stopped after the timeout of 0.3 s (--timeout)");
  EXPECT_LT(out["end_time"].get<double>(), 600.0);
  EXPECT_LT(seconds, 30.0);  // 600 simulated seconds take about 13 s of wall time uninterrupted
}

}  // namespace
