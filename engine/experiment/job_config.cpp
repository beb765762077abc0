#include "engine/experiment/job_config.hpp"

namespace armfarm {
namespace {

/// Appends `keys` of the member that `member` selects, under `prefix`.
template <typename Struct, typename Select>
void append_keys(std::vector<JobConfigKey>& out, const std::string& prefix, const std::vector<ConfigKey<Struct>>& keys, Select member) {
  for (const ConfigKey<Struct>& key : keys) {
    auto field = key.field;
    out.push_back({prefix + key.name, key.unit, key.range, key.size, key.doc,
                   [member, field](JobConfig& config) { return field(member(config)); }});
  }
}

const std::vector<ConfigKey<JobConfig>>& top_level_keys() {
  using C = JobConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"active_joints", "", closed(1, 1000), ListSize::joint_numbers,
       "1-based joint numbers that move (the thesis's \"joint 2\"); the others are locked at their start angles; [] = all",
       [](C& c) { return make_field(c.active_joints); }},
      {"seed", "", closed(0, 9.2e18), ListSize::any, "draws the reaching targets and the batch train/test split and shuffles",
       [](C& c) { return make_integer_field(c.seed); }},
      {"start_posture", "rad", {}, ListSize::movable_joints,
       "where the joints start (rad; m for sliders), one per joint of the model, active or locked, each inside its limits; "
       "[] = the model's (the file's start positions, else 0 clamped into the middle half of each joint's range)",
       [](C& c) { return make_field(c.start_posture); }},
  };
  return keys;
}

std::vector<JobConfigKey> make_job_config_keys() {
  std::vector<JobConfigKey> keys;
  append_keys(keys, "", top_level_keys(), [](JobConfig& c) -> JobConfig& { return c; });
  append_keys(keys, "end_effector.", end_effector_config_keys(), [](JobConfig& c) -> EndEffectorConfig& { return c.end_effector; });
  append_keys(keys, "", simulation_config_keys(), [](JobConfig& c) -> SimulationConfig& { return c.simulation; });
  append_keys(keys, "control.", control_config_keys(), [](JobConfig& c) -> ControlConfig& { return c.control; });
  append_keys(keys, "trajectory.", trajectory_config_keys(), [](JobConfig& c) -> TrajectoryConfig& { return c.trajectory; });
  append_keys(keys, "trajectory.sine.", sine_trajectory_config_keys(),
              [](JobConfig& c) -> SineTrajectoryConfig& { return c.trajectory.sine; });
  append_keys(keys, "trajectory.figure_eight.", figure_eight_config_keys(),
              [](JobConfig& c) -> FigureEightConfig& { return c.trajectory.figure_eight; });
  append_keys(keys, "trajectory.reaching.", reaching_config_keys(), [](JobConfig& c) -> ReachingConfig& { return c.trajectory.reaching; });
  append_keys(keys, "trajectory.recorded.", recorded_trajectory_config_keys(),
              [](JobConfig& c) -> RecordedTrajectoryConfig& { return c.trajectory.recorded; });
  append_keys(keys, "learning.", learning_config_keys(), [](JobConfig& c) -> LearningConfig& { return c.learning; });
  append_keys(keys, "learning.lwpr.", lwpr_params_keys(), [](JobConfig& c) -> lwpr::LwprParams& { return c.learning.lwpr; });
  append_keys(keys, "learning.ssgpr.", ssgpr_learning_config_keys(), [](JobConfig& c) -> SsgprLearningConfig& { return c.learning.ssgpr; });
  append_keys(keys, "mismatch.", mismatch_config_keys(), [](JobConfig& c) -> MismatchConfig& { return c.mismatch; });
  append_keys(keys, "recording.", recording_config_keys(), [](JobConfig& c) -> RecordingConfig& { return c.recording; });
  append_keys(keys, "divergence.", divergence_config_keys(), [](JobConfig& c) -> DivergenceConfig& { return c.divergence; });
  append_keys(keys, "statistics.", statistics_config_keys(), [](JobConfig& c) -> StatisticsConfig& { return c.statistics; });
  return keys;
}

}  // namespace

const std::vector<JobConfigKey>& job_config_keys() {
  static const std::vector<JobConfigKey> keys = make_job_config_keys();
  return keys;
}

}  // namespace armfarm
