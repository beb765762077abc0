// The experiment job's JSON configuration: defaults parse into the engine's defaults, values
// land in the right fields, and bad values name their JSON path.
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

std::string error_of(const nlohmann::json& config) {
  try {
    parse_job_config(config, 7);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(JobConfigJson, DefaultsParseToTheEngineDefaults) {
  const JobConfig parsed = parse_job_config(make_job_config_defaults(), 7);
  const JobConfig engine;
  EXPECT_EQ(parsed.simulation.dt, engine.simulation.dt);
  EXPECT_EQ(parsed.control.gain_scale, engine.control.gain_scale);
  EXPECT_EQ(parsed.control.bandwidth, engine.control.bandwidth);
  EXPECT_EQ(parsed.learning.lwpr.init_D(0, 0), make_job_lwpr_defaults().init_D(0, 0));
  EXPECT_EQ(parsed.learning.lwpr.trust_n_data, 5.0);
  EXPECT_EQ(parsed.trajectory.figure_eight.points_per_loop, 750);
  EXPECT_EQ(parsed.divergence.velocity_limit_factor, engine.divergence.velocity_limit_factor);
  EXPECT_TRUE(parsed.active_joints.empty());
}

TEST(JobConfigJson, ValuesLandInTheirFields) {
  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {2, 3, 6, 7};
  config["control"]["kp"] = {10, 20, 30, 40};
  config["control"]["mode"] = "feedback";
  config["learning"]["lwpr"]["init_D"] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  config["trajectory"]["kind"] = "figure_eight";
  config["mismatch"]["payload"]["mass"] = 2.5;
  const JobConfig parsed = parse_job_config(config, 7);
  EXPECT_EQ(parsed.active_joints, (std::vector<int>{2, 3, 6, 7}));
  EXPECT_EQ(parsed.control.kp[3], 40.0);
  EXPECT_EQ(parsed.control.mode, ControlMode::feedback);
  EXPECT_EQ(parsed.learning.lwpr.init_D.size(), 12);
  EXPECT_EQ(parsed.trajectory.kind, TrajectoryKind::figure_eight);
  EXPECT_EQ(parsed.mismatch.payload.mass, 2.5);
}

TEST(JobConfigJson, BadValuesNameTheirPath) {
  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {2, 8};
  EXPECT_NE(error_of(config).find("active_joints[1]: joint 8 does not exist"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["control"]["mode"] = "pid";
  EXPECT_NE(error_of(config).find("control.mode: must be one of"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["control"]["kp"] = {1, 2, 3};
  EXPECT_NE(error_of(config).find("control.kp: has 3 values"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["learning"]["lwpr"]["w_gen"] = 2.0;
  EXPECT_NE(error_of(config).find("learning.lwpr"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["recording"]["series"] = {"POS", "TORQUE"};
  EXPECT_NE(error_of(config).find("recording.series[1]: unknown name"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["learning"]["mode"] = "none";
  EXPECT_NE(error_of(config).find("learning.mode"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = "/nonexistent/motion.csv";
  EXPECT_NE(error_of(config).find("trajectory.recorded.file: /nonexistent/motion.csv"), std::string::npos) << error_of(config);
}

}  // namespace
}  // namespace armfarm
