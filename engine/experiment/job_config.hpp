#pragma once
// Everything one experiment job needs, as a plain immutable description. JobConfig only
// aggregates the components' own configuration structs, each beside its code with the only
// copy of its defaults and its key table:
//   simulation  engine/physics/simulation_config.hpp    (keys at the top level: dt, integrator, …)
//   control     engine/control/control_config.hpp
//   trajectory  engine/trajectory/trajectory_config.hpp
//   learning    engine/learning/learning_config.hpp     (learning.lwpr: LWPR's parameter block;
//                                                        learning.ssgpr: ssgpr_learning_config.hpp)
//   mismatch, recording, divergence, statistics  engine/experiment/*_config.hpp
//   end_effector  engine/model/end_effector.hpp  } applied to the model by make_job_model
//   start_posture engine/model/start_posture.hpp } (engine/experiment/job_model.hpp)
// job_config_keys() concatenates their tables under their dotted prefixes; the runner's JSON
// reader and writer, validate() (job_config_validation.hpp) and the documentation check use it.
// The engine never reads JSON.
//
// Units: SI and radians. Per-joint vectors have one entry per active joint, in the order of
// `active_joints`; a 1-element vector applies to every active joint; an empty vector means
// "the default rule" stated at the field.
#include "engine/config/config_key.hpp"
#include "engine/control/control_config.hpp"
#include "engine/experiment/divergence_config.hpp"
#include "engine/experiment/mismatch_config.hpp"
#include "engine/experiment/recording_config.hpp"
#include "engine/experiment/statistics_config.hpp"
#include "engine/learning/learning_config.hpp"
#include "engine/model/end_effector.hpp"
#include "engine/physics/simulation_config.hpp"
#include "engine/trajectory/trajectory_config.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace armfarm {

struct JobConfig {
  std::vector<int> active_joints;  ///< 1-based movable joint numbers (the thesis's "Joint 2"); empty = all
  std::uint64_t seed = 0;          ///< draws the reaching targets and the batch split and shuffles
  EndEffectorConfig end_effector;  ///< which link (and point on it) tracks task-space targets; applied by make_job_model
  /// rad or m, one per movable joint (joint-number order, active or locked): where the job starts
  /// and locked joints stay; empty = the model's (the file's, else start_posture.hpp's default).
  /// Applied by make_job_model (job_model.hpp).
  Eigen::VectorXd start_posture;
  SimulationConfig simulation;
  ControlConfig control;
  TrajectoryConfig trajectory;
  LearningConfig learning;
  MismatchConfig mismatch;
  RecordingConfig recording;
  DivergenceConfig divergence;
  StatisticsConfig statistics;
};

/// One key of a job configuration with its full dotted path ("trajectory.sine.duration").
struct JobConfigKey {
  std::string path;
  const char* unit;
  Range range;
  ListSize size;
  const char* doc;
  std::function<FieldRef(JobConfig& config)> field;
};

/// Every key of a job configuration, in documentation order.
const std::vector<JobConfigKey>& job_config_keys();

}  // namespace armfarm
