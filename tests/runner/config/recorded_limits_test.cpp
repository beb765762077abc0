// Recorded joint-space trajectories are checked against the model's joint limits before any job
// runs: the first sample outside them is refused with its file line (issue 16).
#include "engine/model/model_loading.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace armfarm {
namespace {

// A 7-column joint-space recording of 20 rows at 0.1 rad, with `bad_row` (0-based data row,
// -1 for none) set to `value` in column `column`; a comment-free header on line 1.
std::string write_recording(const std::string& name, int bad_row, int column, double value) {
  const std::string path = test_support::scratch_file(name);
  std::ofstream out(path);
  out << "q1,q2,q3,q4,q5,q6,q7\n";
  for (int r = 0; r < 20; ++r) {
    if (r == 3) out << "\n";  // a blank line: file lines and rows differ from here on
    for (int c = 0; c < 7; ++c) out << (c ? "," : "") << (r == bad_row && c == column ? value : 0.1 + 0.001 * r);
    out << "\n";
  }
  return path;
}

nlohmann::json make_recorded_config(const std::string& file) {
  nlohmann::json config = make_job_config_defaults();
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = file;
  config["trajectory"]["recorded"]["task_space"] = false;
  return config;
}

ModelFacts make_symmetric_facts(double limit) {
  ModelFacts facts;
  facts.movable_joints = 7;
  facts.lower_limits.assign(7, -limit);
  facts.upper_limits.assign(7, limit);
  return facts;
}

std::string error_of(const nlohmann::json& config, const ModelFacts& facts) {
  try {
    parse_job_config(config, facts);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(RecordedLimits, TheFirstAngleOutsideItsLimitsIsRefusedWithItsLine) {
  // Data row 5 sits on file line 8 (the header, then a blank line after the third row).
  const std::string path = write_recording("limits_bad.csv", 5, 2, 100.0);
  const std::string error = error_of(make_recorded_config(path), make_symmetric_facts(2.0));
  std::remove(path.c_str());
  EXPECT_EQ(error.rfind("trajectory.recorded.file: " + path + ":8: ", 0), 0u) << error;
  EXPECT_NE(error.find(path + ":8: joint 3 angle 100 rad (column 3) is outside its limits [-2, 2] rad (the first sample outside them)"),
            std::string::npos)
      << error;
}

TEST(RecordedLimits, ARecordingWithinTheLimitsIsAccepted) {
  const std::string path = write_recording("limits_ok.csv", -1, 0, 0.0);
  EXPECT_EQ(error_of(make_recorded_config(path), make_symmetric_facts(2.0)), "(accepted)");
  // Without limits (the joint-count-only overload), 100 rad is not checked here.
  const std::string wild = write_recording("limits_unchecked.csv", 5, 2, 100.0);
  EXPECT_NO_THROW(parse_job_config(make_recorded_config(wild), 7));
  std::remove(path.c_str());
  std::remove(wild.c_str());
}

TEST(RecordedLimits, ActiveJointsMapColumnsToTheirJoints) {
  // Two active joints, 2 and 5: column 2 is joint 5, whose limit here is 0.5 rad.
  const std::string path = test_support::scratch_file("limits_active.csv");
  {
    std::ofstream out(path);
    out << "a,b\n";
    for (int r = 0; r < 20; ++r) out << "0.2," << (r == 10 ? 0.7 : 0.1) << "\n";
  }
  nlohmann::json config = make_recorded_config(path);
  config["active_joints"] = {2, 5};
  ModelFacts facts = make_symmetric_facts(3.0);
  facts.lower_limits[4] = -0.5;
  facts.upper_limits[4] = 0.5;
  const std::string error = error_of(config, facts);
  std::remove(path.c_str());
  EXPECT_NE(error.find(path + ":12: joint 5 angle 0.7 rad (column 2) is outside its limits [-0.5, 0.5] rad"), std::string::npos)
      << error;
}

TEST(RecordedLimits, ModelFactsCarryTheLwrLimits) {
  const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  const ModelFacts facts = make_model_facts(model);
  ASSERT_EQ(facts.movable_joints, 7);
  ASSERT_EQ(facts.lower_limits.size(), 7u);
  const Joint& first = model.joints[model.movable_joints()[0]];
  ASSERT_TRUE(first.has_position_limits);
  EXPECT_EQ(facts.lower_limits[0], first.lower);
  EXPECT_EQ(facts.upper_limits[0], first.upper);
  for (int j = 0; j < 7; ++j) EXPECT_LT(facts.lower_limits[j], facts.upper_limits[j]);
}

}  // namespace
}  // namespace armfarm
