#pragma once
// The one validation of a job configuration, run before anything is built or stored: every
// key's range from the key tables (job_config.hpp), list sizes against the model's joints,
// the cross-field rules, LWPR's and SSGPR's parameter shapes, and the job's cost bound. The runner calls it
// (through parse_job_config) for every job of a sweep before the database is opened; the
// engine's run_experiment() takes the ValidJobConfig that check_job_config makes as the proof,
// and validates only a plain JobConfig (one check at its entry).
#include "engine/experiment/job_config.hpp"
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

/// One problem: the key path ("trajectory.figure_eight.scale", "control.kp[2]") and what is
/// wrong, with the value, its unit and the allowed range.
struct ConfigProblem {
  std::string path;            ///< a configuration path's text (base/config_path.hpp); "" for the whole
  std::string message;         ///< what is wrong, without the path
  std::string unit;            ///< the key's unit ("rad", "s") when the value is outside its range, else ""
  std::optional<Range> range;  ///< the range the value is outside, else empty
};

/// A configuration problem found where a value is used rather than in validate() (the start
/// posture against the model a job runs on): what() is "path: message", and the problem is
/// carried whole so that a caller never cuts the text up.
class ConfigProblemError : public std::invalid_argument {
 public:
  explicit ConfigProblemError(ConfigProblem problem)
      : std::invalid_argument(problem.path.empty() ? problem.message : problem.path + ": " + problem.message),
        problem_(std::move(problem)) {}
  const ConfigProblem& problem() const { return problem_; }

 private:
  ConfigProblem problem_;
};

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

/// Bounds on a job's cost, so that a typo cannot occupy a core for days. At the measured
/// 45 simulated seconds per wall second of the default job (dt = 0.01 s, 7 joints, online LWPR;
/// sweeps/README.md), 5e6 control ticks take about 20 minutes of wall time.
struct JobCostLimits {
  double max_control_ticks = 5e6;    ///< over all passes (batch: collect_repeats + 1; held-out: 1 + one per checkpoint)
  double max_learner_updates = 2e7;  ///< online ticks, or epochs × training samples (+ evaluation updates)
  /// SSGPR: updates × (2·features)² + fit_samples³ × fit_iterations. At the measured ~0.5 µs per
  /// (2D)²/1000 of an update (engine/ssgpr/README.md: 478 µs at D = 500) and ~2.5e9 fit units
  /// per second, 4e12 is about half an hour of wall time.
  double max_ssgpr_work = 4e12;
};

/// Control ticks of one pass over the configured trajectory at `config.simulation.dt`
/// (sine: duration/dt; figure-eight: points × loops; reaching: points × reaches; recorded:
/// length/dt × loops, 0 when no samples are loaded). Real-valued so that nothing overflows.
double calc_ticks_per_pass(const JobConfig& config);

/// Control ticks of one held-out pass over the held-out trajectory of a job with `n` active
/// joints (engine/experiment/heldout_evaluation.hpp; the job makes one collection pass and one
/// control pass per checkpoint over it); 0 when the job has no held-out evaluation.
double calc_heldout_ticks_per_pass(const JobConfig& config, int n);

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

 private:
  explicit ValidJobConfig(JobConfig config) : config_(std::move(config)) {}
  friend std::variant<ValidJobConfig, std::vector<ConfigProblem>> check_job_config(JobConfig config, const ModelFacts& facts,
                                                                                   const JobCostLimits& limits);
  friend class PackedValidJobConfig;  // packed_job_config.hpp: unpacks what a ValidJobConfig packed
  JobConfig config_;
};

}  // namespace armfarm
