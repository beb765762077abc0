// Building a job's trajectory (build_trajectory): the sine trajectory's derivatives match the
// closed form, a recorded task-space path is resampled and followed, the reaching trajectory is
// deterministic in its seed and stays in its box.
#include "engine/trajectory/trajectory.hpp"
#include "engine/model/arm_reach.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/trajectory/trajectory_config.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace armfarm {
namespace {

TEST(SineTrajectory, DerivativesMatchTheClosedForm) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model, {1, 3});
  TrajectoryConfig config;
  config.sine.amplitude = Eigen::Vector2d(0.2, 0.4);
  config.sine.frequency = Eigen::Vector2d(0.5, 0.25);
  config.sine.duration = 4.0;
  const JointTrajectory analytic = build_trajectory(config, dynamics, 0.01, 0);
  ASSERT_EQ(analytic.size(), 400);
  EXPECT_NEAR(analytic.q(0, 0), dynamics.start_positions()[0], 1e-12) << "offset defaults to the start angle";
  const double w = 2.0 * M_PI * 0.5, t = 123 * 0.01;
  EXPECT_NEAR(analytic.qd(123, 0), 0.2 * w * std::cos(w * t), 1e-12);
  EXPECT_NEAR(analytic.qdd(123, 0), -0.2 * w * w * std::sin(w * t), 1e-12);
  EXPECT_EQ(analytic.segment_starts, (std::vector<int>{0}));  // one period of the slowest joint
  config.differentiation = Differentiation::backward_difference;
  const JointTrajectory backward = build_trajectory(config, dynamics, 0.01, 0);
  EXPECT_NEAR(backward.qd(123, 1), (backward.q(123, 1) - backward.q(122, 1)) / 0.01, 1e-12);
  // The thesis's backward difference lags half a tick: its error is O(dt), visibly larger.
  EXPECT_GT(std::fabs(backward.qd(123, 0) - analytic.qd(123, 0)), 1e-3);
  config.differentiation = Differentiation::smoothed;
  const JointTrajectory smoothed = build_trajectory(config, dynamics, 0.01, 0);
  EXPECT_NEAR(smoothed.qd(123, 0), analytic.qd(123, 0), 1e-4);
}

TEST(RecordedTrajectory, TaskSpaceSamplesAreResampledAndFollowed) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  TrajectoryConfig config;
  config.kind = TrajectoryKind::recorded;
  config.recorded.sample_rate = 50.0;  // resampled to 100 Hz
  config.recorded.samples.resize(101, 3);
  const Eigen::Vector3d centre = dynamics.calc_end_effector_position(dynamics.start_positions());
  for (int i = 0; i <= 100; ++i) {
    const double t = i / 50.0;
    config.recorded.samples.row(i) = (centre + Eigen::Vector3d(0.0, 0.05 * std::sin(M_PI * t), 0.03 * t)).transpose();
  }
  const JointTrajectory trajectory = build_trajectory(config, dynamics, 0.01, 0);
  ASSERT_EQ(trajectory.size(), 201);
  const Eigen::Vector3d halfway = dynamics.calc_end_effector_position(trajectory.q.row(100).transpose());
  EXPECT_LT((halfway - (centre + Eigen::Vector3d(0.0, 0.05 * std::sin(M_PI), 0.03))).norm(), 2e-3);
  config.recorded.samples.conservativeResize(101, 2);
  EXPECT_THROW(build_trajectory(config, dynamics, 0.01, 0), std::invalid_argument);
}

TEST(ReachingTrajectory, IsDeterministicInTheSeedAndStaysInTheBox) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  TrajectoryConfig config;
  config.kind = TrajectoryKind::reaching;
  config.reaching.reaches = 3;
  const JointTrajectory a = build_trajectory(config, dynamics, 0.01, 7), b = build_trajectory(config, dynamics, 0.01, 7);
  const JointTrajectory c = build_trajectory(config, dynamics, 0.01, 8);
  EXPECT_EQ(a.q, b.q);
  EXPECT_GT((a.q - c.q).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_EQ(a.segment_starts, (std::vector<int>{0, 100, 200}));
  for (int k = 0; k < a.size(); ++k) {
    const Eigen::Vector3d p = a.task_position.row(k).transpose();
    const ReachingBox box = calc_reaching_box(config.reaching, calc_reach(dynamics.model()));
    EXPECT_TRUE((p.array() >= box.min.array() - 1e-12).all() && (p.array() <= box.max.array() + 1e-12).all());
    EXPECT_LT((dynamics.calc_end_effector_position(a.q.row(k).transpose()) - p).norm(), 1e-3);
  }
  // Minimum jerk: each reach starts at rest.
  EXPECT_LT(a.qd.row(100).cwiseAbs().maxCoeff(), 0.05);
}

}  // namespace
}  // namespace armfarm
