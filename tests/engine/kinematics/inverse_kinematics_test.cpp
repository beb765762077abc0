// Inverse kinematics: the solution's forward kinematics hits the target, limits hold, and the
// solution depends on the target alone (so closed paths close).
#include "engine/kinematics/inverse_kinematics.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "../physics/test_arms.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

namespace armfarm {
namespace {

TEST(InverseKinematics, ReachesRandomReachableTargetsWithinLimits) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  const Eigen::VectorXd rest = dynamics.start_positions();
  std::mt19937_64 generator(3);
  std::uniform_real_distribution<double> offset(-0.4, 0.4);
  int solved = 0;
  for (int trial = 0; trial < 20; ++trial) {
    // Targets produced by the arm itself are reachable by construction.
    Eigen::VectorXd q_true = rest;
    for (int j = 0; j < q_true.size(); ++j) q_true[j] += offset(generator);
    const Eigen::Vector3d target = dynamics.calc_end_effector_position(q_true);
    const InverseKinematicsResult result = solve_inverse_kinematics(dynamics, target, rest, rest);
    EXPECT_TRUE(result.converged) << "trial " << trial << " error " << result.error;
    EXPECT_LT((dynamics.calc_end_effector_position(result.q) - target).norm(), 1e-5);
    EXPECT_TRUE((result.q.array() >= dynamics.lower_limits().array()).all());
    EXPECT_TRUE((result.q.array() <= dynamics.upper_limits().array()).all());
    solved += result.converged;
  }
  EXPECT_EQ(solved, 20);
  std::printf("end effector at the start posture: %.3f %.3f %.3f m\n", dynamics.calc_end_effector_position(rest).x(),
              dynamics.calc_end_effector_position(rest).y(), dynamics.calc_end_effector_position(rest).z());
}

TEST(InverseKinematics, SolutionDependsOnTheTargetNotOnTheStart) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  const Eigen::VectorXd rest = dynamics.start_positions();
  const Eigen::Vector3d target = dynamics.calc_end_effector_position(rest) + Eigen::Vector3d(0.05, -0.08, 0.04);
  const Eigen::VectorXd from_rest = solve_inverse_kinematics(dynamics, target, rest, rest).q;
  const Eigen::VectorXd shifted_start = rest + Eigen::VectorXd::Constant(rest.size(), 0.05);
  const Eigen::VectorXd from_elsewhere = solve_inverse_kinematics(dynamics, target, shifted_start, rest).q;
  EXPECT_LT((from_rest - from_elsewhere).cwiseAbs().maxCoeff(), 1e-5);
}

}  // namespace
}  // namespace armfarm
