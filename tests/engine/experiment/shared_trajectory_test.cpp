// A job run on a trajectory built beforehand (and shared with another job) gives the same
// outcome, bit for bit, as the job building its own; the trajectory inputs are what decides.
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "../physics/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>
#include <string>

namespace armfarm {
namespace {

/// A short online reaching job on joints 1, 2, 4 with the held-out evaluation on.
JobConfig make_reaching_config() {
  JobConfig config;
  config.active_joints = {1, 2, 4};
  config.seed = 3;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.reaches = 4;
  config.trajectory.reaching.points_per_reach = 60;
  config.learning.mode = LearningMode::online;
  config.learning.heldout = true;
  config.learning.heldout_segments = 2;
  config.recording.series = {"TRIAL", "RF"};
  return config;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_identical(const JobOutcome& a, const JobOutcome& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  EXPECT_TRUE(same_bits(a.end_time, b.end_time));
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  int compared = 0;
  for (std::size_t i = 0; i < a.metrics.size(); ++i) {
    const Metric& x = a.metrics[i];
    const Metric& y = b.metrics[i];
    ASSERT_EQ(x.name, y.name);
    EXPECT_EQ(x.joint, y.joint) << x.name;
    if (find_metric_info(x.name).kind == MetricKind::timing) continue;
    ASSERT_EQ(x.value.has_value(), y.value.has_value()) << x.name;
    if (x.value) { EXPECT_TRUE(same_bits(*x.value, *y.value)) << x.name << ": " << *x.value << " vs " << *y.value; }
    ++compared;
  }
  EXPECT_GT(compared, 30);
  ASSERT_EQ(a.series.size(), b.series.size());
  for (std::size_t s = 0; s < a.series.size(); ++s) {
    ASSERT_EQ(a.series[s].rows.rows(), b.series[s].rows.rows()) << a.series[s].name;
    ASSERT_EQ(a.series[s].rows.cols(), b.series[s].rows.cols()) << a.series[s].name;
    EXPECT_EQ(std::memcmp(a.series[s].rows.data(), b.series[s].rows.data(), sizeof(double) * a.series[s].rows.size()), 0)
        << a.series[s].name;
  }
}

TEST(SharedTrajectory, JobOnASharedBuildIsBitIdenticalToOneThatBuildsItsOwn) {
  const ArmModel model = testing::load_lwr3();
  const JobConfig config = make_reaching_config();
  // The build comes from another job of the sweep: equal trajectory inputs, other gains and LWPR.
  JobConfig other = config;
  other.control.gain_scale = 0.2;
  other.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 2.0);
  const JobTrajectories shared = build_job_trajectories(model, other);
  ASSERT_TRUE(shared.heldout.has_value());
  const JobOutcome rebuilt = run_experiment(model, config);
  const JobOutcome reused = run_experiment(model, config, shared);
  ASSERT_EQ(rebuilt.status, JobStatus::done) << rebuilt.message;
  expect_identical(rebuilt, reused);
  // Shared read-only: a second job on the same build gives the same again.
  expect_identical(rebuilt, run_experiment(model, config, shared));
}

TEST(SharedTrajectory, BuildDependsOnTrajectoryInputsOnly) {
  const ArmModel model = testing::load_lwr3();
  const JobConfig config = make_reaching_config();
  const JobTrajectories base = build_job_trajectories(model, config);
  JobConfig gains = config;
  gains.control.gain_scale = 0.3;
  gains.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 0.5);
  gains.simulation.integrator = IntegratorKind::runge_kutta_merson;
  EXPECT_FALSE(is_trajectory_input("control.gain_scale"));
  EXPECT_FALSE(is_trajectory_input("integrator"));
  EXPECT_EQ(build_job_trajectories(model, gains).training.q, base.training.q);
  JobConfig seed = config;
  seed.seed = 4;
  EXPECT_TRUE(is_trajectory_input("seed"));
  EXPECT_NE(build_job_trajectories(model, seed).training.q, base.training.q);
  JobConfig reaches = config;
  reaches.learning.heldout_segments = 3;
  EXPECT_TRUE(is_trajectory_input("learning.heldout_segments"));
  EXPECT_NE(build_job_trajectories(model, reaches).heldout->q.rows(), base.heldout->q.rows());
  for (const char* path : {"trajectory.kind", "trajectory.reaching.reaches", "dt", "active_joints"}) {
    EXPECT_TRUE(is_trajectory_input(path)) << path;
  }
}

TEST(SharedTrajectory, TrajectoryInputsAreKeys) {
  // Every input the builder reads outside the trajectory block is a real key (no misspelt name
  // that would silently leave a field out of the runner's trajectory key).
  std::set<std::string> inputs;
  for (const JobConfigKey& key : job_config_keys()) {
    if (is_trajectory_input(key.path) && key.path.rfind("trajectory.", 0) != 0) inputs.insert(key.path);
  }
  EXPECT_EQ(inputs, (std::set<std::string>{"dt", "seed", "active_joints", "armature_scale", "end_effector.link", "end_effector.offset", "learning.mode", "learning.heldout",
                                           "learning.heldout_amplitude_scale", "learning.heldout_phase_step",
                                           "learning.heldout_segments", "learning.heldout_recorded_fraction", "start_posture"}));
}

}  // namespace
}  // namespace armfarm
