// Reaching on an active-joint subset (the thesis's 3-DOF arm of section 6.2.2, joints 1, 2, 4):
// the serial-chain IK's joint path, checked with Simbody's forward kinematics, follows the
// task-space targets, stays within the velocity bound the builder promises, and is a function
// of the config and seed.
#include "engine/physics/arm_simulation.hpp"
#include "engine/trajectory/trajectory.hpp"
#include "../physics/test_arms.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(ReachingTrajectory, ThreeJointArmFollowsItsTargetsWithinTheVelocityBound) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model, {0, 1, 3});
  TrajectoryConfig config;
  config.kind = TrajectoryKind::reaching;
  config.reaching.reaches = 20;
  const JointTrajectory a = build_trajectory(config, dynamics, 0.01, 3);
  const JointTrajectory b = build_trajectory(config, dynamics, 0.01, 3);
  ASSERT_EQ(a.size(), 2000);
  ASSERT_EQ(a.q.cols(), 3);
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.task_position, b.task_position);
  double worst = 0.0;
  for (int k = 0; k < a.size(); ++k) {
    const Eigen::Vector3d reached = dynamics.calc_end_effector_position(a.q.row(k).transpose());
    worst = std::max(worst, (reached - a.task_position.row(k).transpose()).norm());
  }
  EXPECT_LT(worst, 1e-5) << "the IK converges to 1 µm; the builder's bound is 1 mm";
  const Eigen::VectorXd bound = 0.8 * dynamics.velocity_limits();
  for (int k = 0; k + 1 < a.size(); ++k) {
    const Eigen::VectorXd speed = (a.q.row(k + 1) - a.q.row(k)).transpose().cwiseAbs() / 0.01;
    ASSERT_TRUE((speed.array() <= bound.array() + 1e-12).all()) << "sample " << k;
  }
  const Eigen::VectorXd lower = dynamics.lower_limits(), upper = dynamics.upper_limits();
  EXPECT_TRUE((a.q.colwise().minCoeff().transpose().array() >= lower.array()).all());
  EXPECT_TRUE((a.q.colwise().maxCoeff().transpose().array() <= upper.array()).all());
}

}  // namespace
}  // namespace armfarm
