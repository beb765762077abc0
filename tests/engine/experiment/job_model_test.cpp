// make_job_model: the one place a job configuration's end effector and start posture reach the
// arm; run_experiment refuses a model that was not made for its configuration.
#include "engine/experiment/job_model.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

const std::string kTwoLeaves = std::string(ARMFARM_TEST_DATA_DIR) + "/arms/kuka_iiwa14.urdf";
const std::string kPanda = std::string(ARMFARM_TEST_DATA_DIR) + "/arms/franka_panda.urdf";

TEST(JobModel, TheConfiguredLinkIsTheEndEffectorAndTheFileStaysAsItWas) {
  const ArmModel file = load_arm_model_file(kTwoLeaves);
  ASSERT_EQ(file.end_effector.link, -1);  // two leaves, no choice in the file
  JobConfig tcp;
  tcp.end_effector.link = "tool_tcp";
  JobConfig flange;
  flange.end_effector.link = "iiwa_link_ee";
  const ArmModel at_tcp = make_job_model(file, tcp), at_flange = make_job_model(file, flange);
  EXPECT_EQ(at_tcp.links[at_tcp.end_effector.link].name, "tool_tcp");
  EXPECT_EQ(at_flange.links[at_flange.end_effector.link].name, "iiwa_link_ee");
  EXPECT_EQ(file.end_effector.link, -1);
  // The two points are 0.10 m apart along the flange normal, at any posture.
  ArmDynamics a(at_tcp), b(at_flange);
  const Eigen::VectorXd q = (Eigen::VectorXd(7) << 0.3, -0.6, 0.2, 1.1, -0.4, 0.7, 0.1).finished();
  EXPECT_NEAR((a.calc_end_effector_position(q) - b.calc_end_effector_position(q)).norm(), 0.10, 1e-12);
  EXPECT_THROW(make_job_model(file, JobConfig()), ModelError);
}

TEST(JobModel, StartPostureReplacesEveryJointsStart) {
  const ArmModel file = load_arm_model_file(kPanda);
  JobConfig config;
  config.start_posture = (Eigen::VectorXd(7) << 0.1, -0.3, 0.0, -2.356, 0.0, 1.571, 0.785).finished();
  EXPECT_TRUE(validate(config, make_model_facts(file)).empty());
  const ArmModel made = make_job_model(file, config);
  const std::vector<int> movable = made.movable_joints();
  for (std::size_t j = 0; j < movable.size(); ++j) {
    EXPECT_EQ(made.joints[movable[j]].start_position, config.start_posture[static_cast<Eigen::Index>(j)]);
  }
  EXPECT_EQ(check_job_model(made, config), "");
  // The file's model does not carry the configured posture: a job refuses it.
  EXPECT_NE(check_job_model(make_job_model(file, JobConfig()), config), "");
  config.start_posture.resize(3);
  EXPECT_THROW(make_job_model(file, config), std::invalid_argument);
}

TEST(JobModel, RunExperimentRefusesAModelNotMadeForItsConfiguration) {
  const ArmModel file = load_arm_model_file(kTwoLeaves);
  JobConfig config;
  config.trajectory.sine.duration = 0.1;
  config.learning.mode = LearningMode::none;
  config.control.feed_forward = FeedForwardSource::none;
  config.end_effector.link = "tool_tcp";
  try {
    run_experiment(file, config);
    FAIL() << "ran on a model with no end effector chosen";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("make_job_model"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace armfarm
