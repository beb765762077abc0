// Inverse kinematics: the solution's forward kinematics hits the target, limits hold, and the
// solution depends on the target alone (so closed paths close).
#include "engine/kinematics/inverse_kinematics.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

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

// A stalled iteration (the null-space pull balanced by the damping on the 3-DOF arm, or by a
// joint limit on the 7-DOF arm) finishes on position alone at once, with the answer the full
// max_iterations give (stall_step = 0 runs them all, as before the stall test existed).
TEST(InverseKinematics, StalledIterationsFinishEarlyWithTheSameAnswer) {
  const ArmModel model = testing::load_lwr3();
  for (const std::vector<int>& active : {std::vector<int>{0, 1, 3}, std::vector<int>{}}) {
    const SerialChain chain = make_end_effector_chain(ArmDynamics(model, active));
    const Eigen::VectorXd rest = chain.start_positions();
    InverseKinematicsOptions exhaustive;
    exhaustive.stall_step = 0.0;
    RandomStream draws(4, "inverse_kinematics_test.stall");
    int stalled = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::Vector3d target(draws.uniform(0.2, 0.7), draws.uniform(0.2, 0.7), draws.uniform(0.0, 0.5));
      const InverseKinematicsResult fast = solve_inverse_kinematics(chain, target, rest, rest);
      const InverseKinematicsResult slow = solve_inverse_kinematics(chain, target, rest, rest, exhaustive);
      EXPECT_EQ(fast.converged, slow.converged) << chain.dof() << " DOF, trial " << trial;
      EXPECT_LT((fast.q - slow.q).cwiseAbs().maxCoeff(), 1e-8) << chain.dof() << " DOF, trial " << trial;
      EXPECT_NEAR(fast.error, slow.error, 1e-8);
      EXPECT_LE(fast.iterations, slow.iterations);
      // Stalled cases: a converged answer that took all iterations before (unreachable targets
      // still take them all: the iteration wanders, it does not stall).
      if (slow.iterations == exhaustive.max_iterations && fast.converged) {
        ++stalled;
        EXPECT_LT(fast.iterations, 100) << chain.dof() << " DOF, trial " << trial;
      }
    }
    EXPECT_GE(stalled, 3) << chain.dof() << " DOF: too few stalled cases exercised";
  }
}

TEST(InverseKinematics, ChainAndDynamicsOverloadsAgree) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model, {0, 1, 3});
  const Eigen::VectorXd rest = dynamics.start_positions();
  const Eigen::Vector3d target = dynamics.calc_end_effector_position(rest) + Eigen::Vector3d(0.03, 0.02, -0.05);
  const InverseKinematicsResult a = solve_inverse_kinematics(dynamics, target, rest, rest);
  const InverseKinematicsResult b = solve_inverse_kinematics(make_end_effector_chain(dynamics), target, rest, rest);
  EXPECT_EQ(a.q, b.q);
  EXPECT_TRUE(a.converged);
  EXPECT_LT((dynamics.calc_end_effector_position(a.q) - target).norm(), 1e-6);
}

}  // namespace
}  // namespace armfarm
