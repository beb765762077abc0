#pragma once
// The small learning job of the held-out and collection tests (tests/engine/experiment/
// heldout_evaluation_test.cpp and collection_pass_test.cpp).
#include "engine/experiment/job_config.hpp"

namespace armfarm::test_support {

/// A small learning job: joints 2 and 4 for the joint-space kinds, all seven for the task-space
/// ones (two joints cannot reach the figure-eight or the reaching box).
inline JobConfig make_learning_config(TrajectoryKind kind) {
  JobConfig config;
  if (kind == TrajectoryKind::sine || kind == TrajectoryKind::recorded) config.active_joints = {2, 4};
  config.trajectory.kind = kind;
  config.trajectory.sine.duration = 4.0;
  config.trajectory.figure_eight.points_per_loop = 200;
  config.trajectory.figure_eight.loops = 1;
  config.trajectory.reaching.reaches = 3;
  config.trajectory.reaching.points_per_reach = 60;
  config.learning.mode = LearningMode::batch;
  config.learning.collect_repeats = 1;
  config.learning.heldout_segments = 2;
  config.control.gain_scale = 0.2;
  return config;
}

}  // namespace armfarm::test_support
