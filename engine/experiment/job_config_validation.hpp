#pragma once
// The one validation of a job configuration, run before anything is built or stored: every
// key's range from the key tables (job_config.hpp), list sizes against the model's joints,
// the cross-field rules, LWPR's and SSGPR's parameter shapes, and the job's cost bound
// (job_workload.hpp: find_cost_problems). The runner calls it
// (through parse_job_config) for every job of a sweep before the database is opened; the
// engine's run_experiment() takes the ValidJobConfig that check_job_config makes as the proof,
// and validates only a plain JobConfig (one check at its entry).
#include "engine/experiment/config_problem.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_workload.hpp"
#include "engine/model/arm_model.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace armfarm {

class StepCheckMemo;

/// What the configuration is checked against, from the model it will run on.
struct ModelFacts {
  int movable_joints = 0;
  /// Position limits per movable joint (rad or m; ±inf where unlimited); empty: not checked.
  std::vector<double> lower_limits{}, upper_limits{};
  /// Per movable joint: velocity limits (rad/s or m/s, +inf where none) and start positions
  /// (rad or m); empty: trajectories are not checked against the velocity limits.
  std::vector<double> velocity_limits{}, start_positions{};
  /// The step-stability facts at the start posture, every movable joint (job_steps.hpp): the
  /// rigid-body mass matrix (armature not included; n × n), the armature and the viscous
  /// damping (n); empty: the PD and integrator steps are not checked.
  Eigen::MatrixXd rigid_mass{};
  Eigen::VectorXd armature{}, damping{};
  /// The rigid-body mass matrix (n × n, every movable joint) at any posture, for a configured
  /// start_posture (thread-safe; unset: not available).
  std::function<Eigen::MatrixXd(const Eigen::VectorXd& q)> rigid_mass_at{};
  /// The gravity stiffness ∂g/∂q (n × n, every movable joint, N·m/rad; make_gravity_stiffness)
  /// at any posture, for the default gains' kp floor (thread-safe; unset: no floor is judged).
  std::function<Eigen::MatrixXd(const Eigen::VectorXd& q)> gravity_stiffness_at{};
  /// Per movable joint, for messages: its name and whether it slides (m) rather than turns (rad).
  std::vector<std::string> joint_names{};
  std::vector<bool> prismatic{};
  /// The step checks of the jobs validated against these facts, reused where their loops are the
  /// same (job_steps.hpp; thread-safe); null: every job's steps are checked afresh.
  std::shared_ptr<StepCheckMemo> step_checks{};
};

/// The facts of `model`: its movable joints, their limits, names and start positions, and the
/// mass matrix at the start posture (a Simbody system is built for it: callers that validate
/// many jobs keep the facts of a model rather than making them per job, and so share the gravity
/// stiffness at the start posture, computed once, and the step checks' memo).
ModelFacts make_model_facts(const ArmModel& model);

/// Every problem of `config` (empty: valid).
std::vector<ConfigProblem> validate(const JobConfig& config, const ModelFacts& facts, const JobCostLimits& limits = {});

/// "path: message; path: message" (one line).
std::string make_problems_text(const std::vector<ConfigProblem>& problems);

class ValidJobConfig;

/// `config` as a ValidJobConfig when validate(config, facts, limits) finds no problem, else
/// every problem. The one way to make a ValidJobConfig.
std::variant<ValidJobConfig, std::vector<ConfigProblem>> check_job_config(JobConfig config, const ModelFacts& facts,
                                                                          const JobCostLimits& limits = {});

/// A JobConfig that validate() found no problem in against the facts of the model it runs on:
/// the proof of the one validation at the edge (the runner's parse_job_config). The engine's
/// entry points that take one (run_experiment, build_job_trajectories) do not validate again;
/// those that take a plain JobConfig validate it once at their entry.
class ValidJobConfig {
 public:
  const JobConfig& get() const { return config_; }
  /// Read like the JobConfig it holds (a copy, where a caller wants one to change).
  operator const JobConfig&() const { return config_; }  // NOLINT(google-explicit-constructor)
  /// Gives up the proof: the configuration itself, moved out (its storage, such as recorded
  /// samples and model bytes, keeps its address), for a caller that takes it apart; this
  /// object is left as a moved-from JobConfig.
  JobConfig release() && { return std::move(config_); }

 private:
  explicit ValidJobConfig(JobConfig config) : config_(std::move(config)) {}
  friend std::variant<ValidJobConfig, std::vector<ConfigProblem>> check_job_config(JobConfig config, const ModelFacts& facts,
                                                                                   const JobCostLimits& limits);
  friend class PackedValidJobConfig;  // packed_job_config.hpp: unpacks what a ValidJobConfig packed
  JobConfig config_;
};

}  // namespace armfarm
