#include "engine/experiment/job_config_validation.hpp"

#include "base/number_format.hpp"
#include "engine/experiment/job_steps.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "engine/lwpr/lwpr_param_problem.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/ssgpr/ssgpr_param_problem.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace armfarm {
namespace {

std::string with_unit(const std::string& text, const char* unit) { return *unit ? text + " " + unit : text; }

class Checker {
 public:
  Checker(std::vector<ConfigProblem>& problems) : problems_(problems) {}

  void add(const std::string& path, const std::string& message) { problems_.push_back({path, message, "", std::nullopt}); }

  void check_number(const JobConfigKey& key, const std::string& path, double value) {
    if (key.range.contains(value)) return;
    problems_.push_back({path,
                         with_unit(format_number(value), key.unit) + " is outside the allowed range " + with_unit(key.range.describe(), key.unit),
                         key.unit, key.range});
  }

  void check_integer(const JobConfigKey& key, const std::string& path, long long value) {
    if (key.range.contains(static_cast<double>(value))) return;
    problems_.push_back({path, std::to_string(value) + " is outside the allowed range " + key.range.describe() + " (integers)",
                         key.unit, key.range});
  }

  void check_elements(const JobConfigKey& key, const Eigen::Ref<const Eigen::VectorXd>& values) {
    for (Eigen::Index i = 0; i < values.size(); ++i) check_number(key, key.path + "[" + std::to_string(i) + "]", values[i]);
  }

  void check_size(const JobConfigKey& key, Eigen::Index size, int n, int movable) {
    const auto plural = [](long count) { return std::to_string(count) + (count == 1 ? " value" : " values"); };
    switch (key.size) {
      case ListSize::per_joint:
        if (size > 1 && size != n) {
          add(key.path, "has " + plural(size) + "; give none (the stated rule), 1 (all joints) or one per active joint (" +
                            std::to_string(n) + ")");
        }
        break;
      case ListSize::lwpr_inputs:
        if (size != 1 && size != 3 * n) {
          add(key.path, "has " + plural(size) + "; give 1 or one per input (3 × " + std::to_string(n) + " active joints = " +
                            std::to_string(3 * n) + ")");
        }
        break;
      case ListSize::lwpr_outputs:
        if (size != 1 && size != n) add(key.path, "has " + plural(size) + "; give 1 or one per active joint (" + std::to_string(n) + ")");
        break;
      case ListSize::movable_joints:
        if (size != 0 && size != movable) {
          add(key.path, "has " + plural(size) + "; give none (the stated rule) or one per joint of the arm (" +
                            std::to_string(movable) + ", active or locked)");
        }
        break;
      default:
        break;
    }
  }

 private:
  std::vector<ConfigProblem>& problems_;
};

bool has_problem_under(const std::vector<ConfigProblem>& problems, const std::string& prefix) {
  return std::any_of(problems.begin(), problems.end(), [&](const ConfigProblem& p) { return p.path.rfind(prefix, 0) == 0; });
}

// A joint-space recording must stay within the model's position limits: the first sample
// outside them is named by its file line (its row when the samples did not come from a file).
void check_recorded_limits(const JobConfig& config, const ModelFacts& facts, Checker& checker) {
  const RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  if (facts.lower_limits.size() != static_cast<std::size_t>(facts.movable_joints) ||
      facts.upper_limits.size() != facts.lower_limits.size()) {
    return;
  }
  for (Eigen::Index r = 0; r < recorded.samples.rows(); ++r) {
    for (Eigen::Index c = 0; c < recorded.samples.cols(); ++c) {
      const int joint = config.active_joints.empty() ? static_cast<int>(c) + 1 : config.active_joints[c];
      if (joint < 1 || joint > facts.movable_joints) return;  // check_joints reports it
      const double lower = facts.lower_limits[joint - 1], upper = facts.upper_limits[joint - 1];
      const double q = recorded.samples(r, c);
      if (q >= lower && q <= upper) continue;
      const bool from_file = recorded.sample_lines.size() == static_cast<std::size_t>(recorded.samples.rows());
      char text[160];
      std::snprintf(text, sizeof text, "joint %d angle %.6g rad (column %d) is outside its limits [%.6g, %.6g] rad", joint,
                    q, static_cast<int>(c) + 1, lower, upper);
      checker.add("trajectory.recorded.file",
                  (from_file ? recorded.file + ":" + std::to_string(recorded.sample_lines[r])
                             : std::string("the samples, row ") + std::to_string(r + 1)) +
                      ": " + text + " (the first sample outside them)");
      return;
    }
  }
}

/// The 1-based joint numbers of the job (every movable joint for an empty list).
std::vector<int> resolve_joint_numbers(const JobConfig& config, const ModelFacts& facts) {
  if (!config.active_joints.empty()) return config.active_joints;
  std::vector<int> numbers;
  for (int j = 1; j <= facts.movable_joints; ++j) numbers.push_back(j);
  return numbers;
}

/// `values` (one per movable joint) at the job's joints.
Eigen::VectorXd select_joints(const std::vector<double>& values, const std::vector<int>& numbers) {
  Eigen::VectorXd selected(static_cast<Eigen::Index>(numbers.size()));
  for (std::size_t i = 0; i < numbers.size(); ++i) selected[static_cast<Eigen::Index>(i)] = values[numbers[i] - 1];
  return selected;
}

// The PD period and integrator steps against the step-stability criterion at the start posture
// (job_steps.hpp): an explicit value it calls unstable, or "auto" finding none, is a problem.
void check_steps(const JobConfig& config, const ModelFacts& facts, Checker& checker) {
  try {
    const std::optional<StartPostureLoops> loops = make_start_posture_loops(config, facts);
    if (!loops) return;
    const std::vector<StepProblem> problems = facts.step_checks
                                                  ? facts.step_checks->check(config, *loops)
                                                  : check_job_steps(config, loops->plants, loops->controllers, loops->joint_numbers);
    for (const StepProblem& problem : problems) checker.add(problem.key, problem.message);
  } catch (const std::invalid_argument& error) {
    checker.add("model", std::string("the step-stability check failed: ") + error.what());
  }
}

// A sine the user set must stay within the joints' position and velocity limits, its held-out
// variant included (the default amplitude keeps within them by construction).
void check_sine_limits(const JobConfig& config, const ModelFacts& facts, Checker& checker) {
  const int movable = facts.movable_joints;
  if (facts.velocity_limits.size() != static_cast<std::size_t>(movable) || facts.start_positions.size() != facts.velocity_limits.size() ||
      facts.lower_limits.size() != facts.velocity_limits.size() || facts.upper_limits.size() != facts.velocity_limits.size()) {
    return;
  }
  const std::vector<int> numbers = resolve_joint_numbers(config, facts);
  const int n = static_cast<int>(numbers.size());
  const JointRanges ranges{select_joints(facts.lower_limits, numbers), select_joints(facts.upper_limits, numbers),
                           select_joints(facts.velocity_limits, numbers)};
  SineTrajectoryConfig sine;
  std::vector<double> start = facts.start_positions;
  if (config.start_posture.size() == movable) start.assign(config.start_posture.data(), config.start_posture.data() + movable);
  try {
    sine = resolve_sine_defaults(config.trajectory.sine, n, select_joints(start, numbers), &ranges);
  } catch (const std::invalid_argument&) {
    return;  // mis-sized lists are reported by their keys
  }
  const LearningConfig& learning = config.learning;
  const bool heldout = learning.mode != LearningMode::none && learning.heldout;
  const double scale = heldout ? std::max(1.0, learning.heldout_amplitude_scale) : 1.0;
  const bool set_amplitude = config.trajectory.sine.amplitude.size() > 0;
  const bool set_frequency = config.trajectory.sine.frequency.size() > 0;
  for (int j = 0; j < n; ++j) {
    const double amplitude = sine.amplitude[j] * scale;
    const double omega = 2.0 * M_PI * sine.frequency[j];
    const double speed = amplitude * omega;
    const std::string joint = "joint " + std::to_string(numbers[static_cast<std::size_t>(j)]);
    const std::string variant = scale > 1.0 ? " (the held-out variant's amplitude, × learning.heldout_amplitude_scale " + format_number(scale) + ")" : "";
    if (speed > ranges.velocity[j]) {
      checker.add(set_frequency || !set_amplitude ? "trajectory.sine.frequency" : "trajectory.sine.amplitude",
                  joint + " needs " + format_number(speed) + " rad/s (amplitude " + format_number(amplitude) + " rad × 2π × " +
                      format_number(sine.frequency[j]) + " Hz" + variant + "), above its velocity limit " +
                      format_number(ranges.velocity[j]) + " rad/s; at this frequency an amplitude of at most " +
                      format_number(ranges.velocity[j] / omega / scale) + " rad keeps within it");
      return;
    }
    const double low = sine.offset[j] - amplitude, high = sine.offset[j] + amplitude;
    if (low < ranges.lower[j] || high > ranges.upper[j]) {
      const double room = std::min(sine.offset[j] - ranges.lower[j], ranges.upper[j] - sine.offset[j]);
      checker.add(set_amplitude ? "trajectory.sine.amplitude" : "trajectory.sine.offset",
                  joint + " would move over [" + format_number(low) + ", " + format_number(high) + "] rad" + variant +
                      ", outside its limits [" + format_number(ranges.lower[j]) + ", " + format_number(ranges.upper[j]) + "] rad" +
                      (room > 0.0 ? "; about offset " + format_number(sine.offset[j]) + " rad an amplitude of at most " +
                                        format_number(room / scale) + " rad keeps within them"
                                  : std::string("; its offset is outside them")));
      return;
    }
  }
}

// A configured start posture must lie inside every joint's limits (1-based joint numbers).
void check_start_posture(const JobConfig& config, const ModelFacts& facts, Checker& checker) {
  const Eigen::VectorXd& posture = config.start_posture;
  if (posture.size() == 0 || facts.lower_limits.size() != static_cast<std::size_t>(posture.size()) ||
      facts.upper_limits.size() != facts.lower_limits.size()) {
    return;
  }
  for (Eigen::Index i = 0; i < posture.size(); ++i) {
    const double lower = facts.lower_limits[i], upper = facts.upper_limits[i];
    if (posture[i] >= lower && posture[i] <= upper) continue;
    const std::string name = static_cast<std::size_t>(i) < facts.joint_names.size() ? " (" + facts.joint_names[i] + ")" : "";
    const bool slider = static_cast<std::size_t>(i) < facts.prismatic.size() && facts.prismatic[i];
    const char* unit = slider ? " m" : " rad";
    checker.add("start_posture[" + std::to_string(i) + "]", "joint " + std::to_string(i + 1) + name + " at " +
                                                            format_number(posture[i]) + unit + " is outside its range [" +
                                                            format_number(lower) + ", " + format_number(upper) + "]" + unit);
  }
}

void check_joints(const JobConfig& config, const ModelFacts& facts, Checker& checker) {
  const std::vector<int>& joints = config.active_joints;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const std::string path = "active_joints[" + std::to_string(i) + "]";
    if (joints[i] < 1 || joints[i] > facts.movable_joints) {
      checker.add(path, "joint " + std::to_string(joints[i]) + " does not exist; the arm has joints 1.." + std::to_string(facts.movable_joints));
    } else if (std::find(joints.begin(), joints.begin() + static_cast<std::ptrdiff_t>(i), joints[i]) != joints.begin() + static_cast<std::ptrdiff_t>(i)) {
      checker.add(path, "joint " + std::to_string(joints[i]) + " is listed twice");
    }
  }
}

void check_key(const JobConfigKey& key, JobConfig& config, int n, int movable, Checker& checker) {
  const FieldRef field = key.field(config);
  switch (field.kind) {
    case ValueKind::real:
      checker.check_number(key, key.path, field.real());
      break;
    case ValueKind::integer:
      checker.check_integer(key, key.path, field.get_integer(field.field));
      break;
    case ValueKind::integer_or_auto:
      if (field.optional_integer()) checker.check_integer(key, key.path, *field.optional_integer());
      break;
    case ValueKind::real_or_auto:
      if (field.optional_real()) checker.check_number(key, key.path, *field.optional_real());
      break;
    case ValueKind::point_or_auto:
      if (field.optional_point()) checker.check_elements(key, *field.optional_point());
      break;
    case ValueKind::choice: {
      const int value = static_cast<int>(field.get_integer(field.field));
      if (std::string(find_enum_name(*field.choices, value)) == "?") {
        checker.add(key.path, "must be " + make_enum_choice_text(*field.choices));
      }
      break;
    }
    case ValueKind::real_list:
    case ValueKind::real_or_list:
      checker.check_size(key, field.vector().size(), n, movable);
      checker.check_elements(key, field.vector());
      break;
    case ValueKind::point:
      checker.check_elements(key, field.point());
      break;
    case ValueKind::real_matrix:
      // Scalar and diagonal metrics element-wise; a full metric must be SPD (checked by LWPR).
      if (field.matrix().cols() == 1) checker.check_elements(key, field.matrix().col(0));
      break;
    case ValueKind::name_list: {
      const std::vector<std::string>& known = field.names();
      const std::vector<std::string>& names = field.texts();
      for (std::size_t i = 0; i < names.size(); ++i) {
        if (std::find(known.begin(), known.end(), names[i]) == known.end()) {
          std::string list;
          for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
          checker.add(key.path + "[" + std::to_string(i) + "]", "unknown name \"" + names[i] + "\" (known: " + list + ")");
        }
      }
      break;
    }
    case ValueKind::integer_list:  // active_joints: check_joints; the others element-wise
      if (key.size != ListSize::joint_numbers) {
        const std::vector<int>& values = field.integers();
        for (std::size_t i = 0; i < values.size(); ++i) checker.check_integer(key, key.path + "[" + std::to_string(i) + "]", values[i]);
      }
      break;
    case ValueKind::boolean:
    case ValueKind::text:
      break;
  }
}

// A learner parameter set's problem at its key path under `prefix` ("learning.lwpr"): a known
// key's own path ("learning.lwpr.init_D", "learning.ssgpr.lengthscales[2]"), else the block's.
void add_param_problem(const ParamProblem& problem, const std::string& prefix, bool known, Checker& checker) {
  if (!known) {
    checker.add(prefix, problem.describe());
    return;
  }
  checker.add(prefix + "." + problem.name + (problem.element ? "[" + std::to_string(*problem.element) + "]" : ""), problem.message);
}

void check_lwpr(const JobConfig& config, int n, const std::vector<ConfigProblem>& problems, Checker& checker) {
  if (has_problem_under(problems, "learning.lwpr.")) return;  // one report per cause
  const std::optional<ParamProblem> problem = lwpr::find_lwpr_param_problem(config.learning.lwpr, 3 * n, n);
  if (!problem) return;
  const auto& keys = lwpr_params_keys();
  const bool known = std::any_of(keys.begin(), keys.end(), [&](const auto& key) { return problem->name == key.name; });
  add_param_problem(*problem, "learning.lwpr", known, checker);
}

// A learner to start from or to store needs a learning mode; a model to start from must read and
// map the job's 3n inputs to its n torques.
void check_initial_model(const LearningConfig& learning, int n, Checker& checker) {
  if (learning.mode == LearningMode::none) {
    if (learning.store_model) checker.add("learning.store_model", "is true but learning.mode is \"none\" (no learner to store)");
    if (!learning.initial_model.empty()) checker.add("learning.initial_model", "is set but learning.mode is \"none\" (no learner)");
    return;
  }
  if (learning.mode == LearningMode::frozen && learning.initial_model.empty()) {
    checker.add("learning.mode", "is \"frozen\" but learning.initial_model is not set (a frozen learner needs a model to start from)");
  }
  if (learning.initial_model_bytes.empty()) return;
  try {
    const std::unique_ptr<Learner> start = decode_learner_model(learning.initial_model_bytes);
    if (start->input_dim() != 3 * n || start->output_dim() != n) {
      checker.add("learning.initial_model", learning.initial_model + " maps " + std::to_string(start->input_dim()) + " inputs to " +
                                                std::to_string(start->output_dim()) + " outputs; this job needs " +
                                                std::to_string(3 * n) + " to " + std::to_string(n) + " (q, q̇, q̈ → τ of " +
                                                std::to_string(n) + " active joints)");
    }
  } catch (const std::exception& error) {
    checker.add("learning.initial_model", learning.initial_model + ": " + error.what());
  }
}

void check_ssgpr(const JobConfig& config, int n, const std::vector<ConfigProblem>& problems, Checker& checker) {
  const SsgprLearningConfig& ssgpr = config.learning.ssgpr;
  if (ssgpr.fit_samples == 1) checker.add("learning.ssgpr.fit_samples", "is 1; give 0 (no fit) or at least 2 samples");
  if (has_problem_under(problems, "learning.ssgpr.")) return;  // one report per cause
  const std::optional<ParamProblem> problem = ssgpr::find_ssgpr_param_problem(ssgpr.params, 3 * n, n);
  if (!problem) return;
  const auto& keys = ssgpr_learning_config_keys();
  const bool known = std::any_of(keys.begin(), keys.end(), [&](const auto& key) { return problem->name == key.name; });
  add_param_problem(*problem, "learning.ssgpr", known, checker);
}

void check_cross_fields(const JobConfig& config, int n, Checker& checker) {
  if (const std::string problem = check_end_effector_config(config.end_effector); !problem.empty()) {
    checker.add("end_effector.offset", problem);
  }
  if (config.control.mode != ControlMode::feedback && config.control.feed_forward == FeedForwardSource::learner &&
      config.learning.mode == LearningMode::none) {
    const auto name = [](const EnumNames& names, auto value) { return std::string("\"") + find_enum_name(names, static_cast<int>(value)) + "\""; };
    checker.add("learning.mode", "is " + name(learning_mode_names(), LearningMode::none) + " but control.feed_forward is " +
                                     name(feed_forward_source_names(), FeedForwardSource::learner) + " (use " +
                                     name(feed_forward_source_names(), FeedForwardSource::analytic) + " or " +
                                     name(feed_forward_source_names(), FeedForwardSource::none) + ")");
  }
  check_initial_model(config.learning, n, checker);
  if (const std::string problem = check_statistics_config(config.statistics); !problem.empty()) checker.add("statistics.window", problem);
  const std::vector<int>& checkpoints = config.learning.heldout_checkpoints;
  for (std::size_t i = 0; i < checkpoints.size(); ++i) {
    if (i > 0 && checkpoints[i] <= checkpoints[i - 1]) {
      checker.add("learning.heldout_checkpoints[" + std::to_string(i) + "]",
                  std::to_string(checkpoints[i]) + " must exceed the checkpoint before it (" + std::to_string(checkpoints[i - 1]) + ")");
    }
  }
  // A box with one corner "auto" is checked once the arm's reach places it (build_reaching).
  const ReachingConfig& reaching = config.trajectory.reaching;
  for (int axis = 0; reaching.box_min && reaching.box_max && axis < 3; ++axis) {
    if (!((*reaching.box_min)[axis] < (*reaching.box_max)[axis])) {
      checker.add("trajectory.reaching.box_max[" + std::to_string(axis) + "]",
                  format_number((*reaching.box_max)[axis]) + " m must exceed box_min[" + std::to_string(axis) + "] = " +
                      format_number((*reaching.box_min)[axis]) + " m");
    }
  }
  const RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  if (recorded.window % 2 == 0) checker.add("trajectory.recorded.window", std::to_string(recorded.window) + " must be odd");
  if (recorded.polynomial_order >= recorded.window) {
    checker.add("trajectory.recorded.polynomial_order",
                std::to_string(recorded.polynomial_order) + " must be below the window (" + std::to_string(recorded.window) + ")");
  }
  if (config.trajectory.kind == TrajectoryKind::recorded) {
    if (recorded.file.empty() && recorded.samples.size() == 0) {
      checker.add("trajectory.recorded.file", std::string("is required when trajectory.kind is \"") +
                                                  find_enum_name(trajectory_kind_names(), static_cast<int>(TrajectoryKind::recorded)) + "\"");
    } else {
      const int columns = recorded.task_space ? 3 : n;
      const std::string where = "trajectory.recorded.file";
      if (recorded.samples.cols() != columns) {
        checker.add(where, (recorded.file.empty() ? std::string("the samples") : recorded.file) + " has " +
                               std::to_string(recorded.samples.cols()) + " columns, expected " + std::to_string(columns) +
                               (recorded.task_space ? " (x, y, z)" : " (one per active joint)"));
      } else if (recorded.samples.rows() < 2) {
        checker.add(where, (recorded.file.empty() ? std::string("the samples") : recorded.file) + " needs at least 2 rows");
      } else if (!recorded.samples.allFinite()) {
        checker.add(where, recorded.file + " holds a NaN or Inf value");
      } else if (const std::string problem = check_recorded_length(recorded, config.simulation.dt); !problem.empty()) {
        checker.add(where, problem);
      }
    }
  }
}

}  // namespace

ModelFacts make_model_facts(const ArmModel& model) {
  ModelFacts facts;
  const std::vector<int> movable = model.movable_joints();
  facts.movable_joints = static_cast<int>(movable.size());
  for (int index : movable) {
    const Joint& joint = model.joints[index];
    const double infinity = std::numeric_limits<double>::infinity();
    facts.lower_limits.push_back(joint.has_position_limits ? joint.lower : -infinity);
    facts.upper_limits.push_back(joint.has_position_limits ? joint.upper : infinity);
    facts.joint_names.push_back(joint.name);
    facts.prismatic.push_back(joint.type == JointType::prismatic);
    facts.velocity_limits.push_back(joint.velocity_limit > 0.0 ? joint.velocity_limit : infinity);
    facts.start_positions.push_back(joint.start_position);
  }
  if (movable.empty()) return facts;
  try {
    // One plant behind a lock: the facts are shared by the threads that validate jobs.
    struct LockedDynamics {
      explicit LockedDynamics(const ArmModel& arm) : model(arm), dynamics(model) {}
      std::mutex mutex;
      ArmModel model;  // its own copy: the dynamics refer to it, and the facts outlive the caller's
      ArmDynamics dynamics;
      Eigen::VectorXd armature;
      Eigen::VectorXd start;                              // the facts' start positions
      std::optional<Eigen::MatrixXd> start_stiffness;  // the gravity stiffness there, once asked for
      // Whether `q` is the start posture, bit for bit (the stiffness there is then the same bits).
      bool is_start(const Eigen::VectorXd& q) const {
        return q.size() == start.size() && std::memcmp(q.data(), start.data(), sizeof(double) * static_cast<std::size_t>(q.size())) == 0;
      }
    };
    auto shared = std::make_shared<LockedDynamics>(model);
    shared->armature.resize(facts.movable_joints);
    for (int j = 0; j < facts.movable_joints; ++j) shared->armature[j] = model.joints[movable[j]].armature;
    facts.armature = shared->armature;
    facts.rigid_mass_at = [shared](const Eigen::VectorXd& q) {
      std::lock_guard<std::mutex> lock(shared->mutex);
      Eigen::MatrixXd mass = shared->dynamics.calc_mass_matrix(q);
      mass.diagonal() -= shared->armature;
      return mass;
    };
    shared->start = Eigen::Map<const Eigen::VectorXd>(facts.start_positions.data(), facts.movable_joints);
    // Every job at the start posture asks for the same matrix (the default gains' kp floor): it
    // is computed once (a sweep's validation spent as long on it as on all else of a job).
    facts.gravity_stiffness_at = [shared](const Eigen::VectorXd& q) -> Eigen::MatrixXd {
      std::lock_guard<std::mutex> lock(shared->mutex);
      if (!shared->is_start(q)) return make_gravity_stiffness(shared->dynamics, q);
      if (!shared->start_stiffness) shared->start_stiffness = make_gravity_stiffness(shared->dynamics, q);
      return *shared->start_stiffness;
    };
    facts.step_checks = std::make_shared<StepCheckMemo>();
    facts.rigid_mass = facts.rigid_mass_at(shared->dynamics.start_positions());
    facts.damping = shared->dynamics.viscous_damping();
  } catch (const std::exception&) {
    facts.rigid_mass.resize(0, 0);  // a model Simbody cannot build fails where the job builds it
    facts.rigid_mass_at = nullptr;
    facts.gravity_stiffness_at = nullptr;
  }
  return facts;
}

std::vector<ConfigProblem> validate(const JobConfig& config, const ModelFacts& facts, const JobCostLimits& limits) {
  std::vector<ConfigProblem> problems;
  Checker checker(problems);
  check_joints(config, facts, checker);
  const int n = config.active_joints.empty() ? facts.movable_joints : static_cast<int>(config.active_joints.size());
  // The key table hands out references to non-const fields; this function only reads them.
  JobConfig& fields = const_cast<JobConfig&>(config);
  for (const JobConfigKey& key : job_config_keys()) check_key(key, fields, n, facts.movable_joints, checker);
  if (n >= 1) check_lwpr(config, n, problems, checker);
  if (n >= 1 && config.learning.learner == LearnerKind::ssgpr) check_ssgpr(config, n, problems, checker);
  check_cross_fields(config, n, checker);
  if (!has_problem_under(problems, "start_posture")) check_start_posture(config, facts, checker);
  // Limits once the recording's shape and values are known good.
  if (config.trajectory.kind == TrajectoryKind::recorded && !config.trajectory.recorded.task_space &&
      !has_problem_under(problems, "trajectory.recorded") && !has_problem_under(problems, "active_joints")) {
    check_recorded_limits(config, facts, checker);
  }
  // The sine and the steps are judged about the start posture: not about one outside the limits.
  const bool sane_joints = !has_problem_under(problems, "active_joints") && !has_problem_under(problems, "start_posture");
  if (sane_joints && config.trajectory.kind == TrajectoryKind::sine && !has_problem_under(problems, "trajectory.") &&
      !has_problem_under(problems, "learning.heldout")) {
    check_sine_limits(config, facts, checker);
  }
  static const char* const step_inputs[] = {"dt", "pd_substeps", "integrator_steps_per_tick", "armature_scale", "control.",
                                            "learning.collect_gain_scale", "mismatch.viscous"};
  if (sane_joints && std::none_of(std::begin(step_inputs), std::end(step_inputs), [&](const char* key) { return has_problem_under(problems, key); })) {
    check_steps(config, facts, checker);
  }
  // The cost needs sane counts and a sane dt; a range problem there is reported already.
  if (!has_problem_under(problems, "dt") && !has_problem_under(problems, "trajectory.") && !has_problem_under(problems, "learning.")) {
    for (ConfigProblem& problem : find_cost_problems(config, n, limits)) problems.push_back(std::move(problem));
  }
  return problems;
}

std::variant<ValidJobConfig, std::vector<ConfigProblem>> check_job_config(JobConfig config, const ModelFacts& facts,
                                                                          const JobCostLimits& limits) {
  std::vector<ConfigProblem> problems = validate(config, facts, limits);
  if (!problems.empty()) return problems;
  return ValidJobConfig(std::move(config));
}

std::string make_problems_text(const std::vector<ConfigProblem>& problems) {
  std::string text;
  for (const ConfigProblem& problem : problems) {
    if (!text.empty()) text += "; ";
    text += problem.path.empty() ? problem.message : problem.path + ": " + problem.message;
  }
  return text;
}

}  // namespace armfarm
