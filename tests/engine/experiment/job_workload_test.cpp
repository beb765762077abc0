// The job-cost model: tick counts against the trajectories the builder makes, the workload's
// passes and updates against counts worked out by hand, and the cost problems' keys and bounds.
#include "engine/experiment/job_workload.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/trajectory/trajectory.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

TEST(JobWorkload, TickCountMatchesTheBuiltTrajectory) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model, {1, 2});
  JobConfig config;
  config.active_joints = {2, 3};
  for (const double duration : {0.5, 2.345, 3.0}) {
    config.trajectory.sine.duration = duration;
    const JointTrajectory trajectory = build_trajectory(config.trajectory, dynamics, config.simulation.dt, config.seed);
    EXPECT_EQ(calc_ticks_per_pass(config), static_cast<double>(trajectory.size())) << duration;
  }
  config.trajectory.kind = TrajectoryKind::recorded;
  config.trajectory.recorded.task_space = false;
  config.trajectory.recorded.filter = RecordedFilter::none;
  config.trajectory.recorded.sample_rate = 30.0;
  config.trajectory.recorded.loops = 2;
  config.trajectory.recorded.samples = Eigen::MatrixXd::Zero(40, 2);
  config.trajectory.recorded.samples.col(0) = Eigen::VectorXd::LinSpaced(40, 0.0, 0.3);
  const JointTrajectory recorded = build_trajectory(config.trajectory, dynamics, config.simulation.dt, config.seed);
  EXPECT_EQ(calc_ticks_per_pass(config), static_cast<double>(recorded.size()));
}

TEST(JobWorkload, HeldOutTickCountMatchesTheBuiltHeldOutTrajectory) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model, {1, 2});
  JobConfig config;
  config.active_joints = {2, 3};
  config.trajectory.sine.frequency = (Eigen::VectorXd(2) << 0.5, 0.2).finished();  // slowest 0.2 Hz: 5 s a period
  for (const int segments : {0, 3}) {
    config.learning.heldout_segments = segments;
    const JobTrajectories built = build_job_trajectories(config, dynamics);
    ASSERT_TRUE(built.heldout.has_value());
    EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), static_cast<double>(built.heldout->size())) << segments;
  }
  EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), 1500.0);  // 3 periods of 5 s at dt = 0.01 s
  config.trajectory.kind = TrajectoryKind::figure_eight;
  config.trajectory.figure_eight.loops = 5;
  config.learning.heldout_segments = 2;
  // (2 joints cannot reach the figure: its count is points × held-out loops.)
  EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), 2.0 * config.trajectory.figure_eight.points_per_loop);
  config.trajectory.kind = TrajectoryKind::recorded;
  config.trajectory.recorded.task_space = false;
  config.trajectory.recorded.filter = RecordedFilter::none;
  config.trajectory.recorded.sample_rate = 30.0;
  config.trajectory.recorded.loops = 2;
  config.trajectory.recorded.samples = Eigen::MatrixXd::Zero(40, 2);
  config.trajectory.recorded.samples.col(0) = Eigen::VectorXd::LinSpaced(40, 0.0, 0.3);
  EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), static_cast<double>(build_job_trajectories(config, dynamics).heldout->size()));
  config.learning.heldout = false;
  EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), 0.0);
  config.learning.heldout = true;
  config.learning.mode = LearningMode::none;
  config.control.feed_forward = FeedForwardSource::none;
  EXPECT_EQ(calc_heldout_ticks_per_pass(config, 2), 0.0);
}

TEST(JobWorkload, PassesHeldOutPassesAndUpdatesAddUpAsCounted) {
  // Batch reaching, 100 points a reach × 10 reaches = 1000 ticks a pass; 3 collection repeats
  // make 4 passes; held-out 4 reaches (400 ticks) collected once and run at 2 checkpoints: 3
  // held-out passes. Training samples: round(0.75 × 3 × 1000) = 2250, × 20 epochs, + one pass
  // learned during evaluation.
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.points_per_reach = 100;
  config.trajectory.reaching.reaches = 10;
  config.learning.mode = LearningMode::batch;
  config.learning.collect_repeats = 3;
  config.learning.train_fraction = 0.75;
  config.learning.epochs = 20;
  config.learning.learn_during_evaluation = true;
  config.learning.heldout = true;
  config.learning.heldout_segments = 4;
  config.learning.heldout_checkpoints = {0, 10};
  const JobWorkload work = calc_job_workload(config, 2);
  EXPECT_EQ(work.ticks_per_pass, 1000.0);
  EXPECT_EQ(work.passes, 4.0);
  EXPECT_EQ(work.heldout_ticks_per_pass, 400.0);
  EXPECT_EQ(work.heldout_passes, 3.0);
  EXPECT_EQ(work.training_ticks, 4000.0);
  EXPECT_EQ(work.control_ticks, 4000.0 + 3 * 400.0);
  EXPECT_EQ(work.learner_updates, 20 * 2250.0 + 1000.0);
  // Online: one update a tick, one pass; no learner: none.
  config.learning.mode = LearningMode::online;
  EXPECT_EQ(calc_job_workload(config, 2).passes, 1.0);
  EXPECT_EQ(calc_job_workload(config, 2).learner_updates, 1000.0);
  config.learning.mode = LearningMode::none;
  config.control.feed_forward = FeedForwardSource::none;
  EXPECT_EQ(calc_job_workload(config, 2).learner_updates, 0.0);
  EXPECT_EQ(calc_job_workload(config, 2).heldout_passes, 0.0);
}

TEST(JobWorkload, CostProblemsNameTheKeyToChangeAndTheBound) {
  JobCostLimits limits;
  limits.max_control_ticks = 1000.0;
  limits.max_learner_updates = 500.0;
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.points_per_reach = 100;
  config.trajectory.reaching.reaches = 10;
  config.learning.heldout = false;
  config.learning.mode = LearningMode::none;
  config.control.feed_forward = FeedForwardSource::none;
  EXPECT_TRUE(find_cost_problems(config, 2, limits).empty());  // 1000 ticks: at the bound
  config.trajectory.reaching.reaches = 11;
  std::vector<ConfigProblem> problems = find_cost_problems(config, 2, limits);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "trajectory.reaching.reaches");
  EXPECT_EQ(problems[0].message.rfind("the job would take 1100 control ticks (1100 per pass × 1 pass at dt = 0.01 s", 0), 0u)
      << problems[0].message;
  // Online with 1000 ticks: 1000 updates over 500, blamed on the length (one per tick).
  config.trajectory.reaching.reaches = 10;
  config.learning.mode = LearningMode::online;
  problems = find_cost_problems(config, 2, limits);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "trajectory.reaching.reaches");
  EXPECT_EQ(problems[0].message, "the learner would be updated 1000 times (one per tick); a job may make at most 500 updates");
  // SSGPR within the tick and update bounds: 400 updates × (2 × 10)² = 160000 units over 1e5.
  config.trajectory.reaching.reaches = 4;
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 10;
  config.learning.ssgpr.fit_samples = 0;
  limits.max_ssgpr_work = 1e5;
  problems = find_cost_problems(config, 2, limits);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "learning.ssgpr.features");
  EXPECT_EQ(problems[0].message.rfind("the SSGPR learner would cost 160000 units (400 updates × (2 × 10 features)²", 0), 0u)
      << problems[0].message;
}

}  // namespace
}  // namespace armfarm
