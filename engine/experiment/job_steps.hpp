#pragma once
// The PD period and integrator steps a job runs with. `auto` (an empty pd_substeps or
// integrator_steps_per_tick) is resolved by the step-stability criterion
// (engine/control/step_stability.hpp) from the job's plant — the mass matrix with armature and
// the joint damping — and its controllers, the gains after their scale; an explicit value is
// taken as it is, and validate() refuses one the criterion calls unstable at the start posture.
#include "engine/control/pd_gains.hpp"
#include "engine/control/step_stability.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_config_validation.hpp"

#include <Eigen/Core>

#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace armfarm {

/// `value` to three significant digits ("%.3g"), as the step and divergence messages print figures.
std::string format_figure(double value);

/// The collection controller's gain scale: learning.collect_gain_scale, or control.gain_scale
/// when it is "auto".
double calc_collect_gain_scale(const JobConfig& config);

/// Whether the job runs passes under the collection controller (batch collection, a held-out set).
bool has_collection_passes(const JobConfig& config);

/// One controller of a job as the plant feels it, and what it is called in messages.
struct JobController {
  LoopGains gains;
  std::string scale_key;  ///< "control.gain_scale" or "learning.collect_gain_scale"
  double scale = 1.0;
};

/// The job's controllers from its full-scale `gains` and the kp floor after scale (empty: none;
/// calc_floored_gains): the evaluation controller (none in open_loop) and, when the job
/// collects, the collection controller (when its scale differs).
std::vector<JobController> make_job_controllers(const JobConfig& config, const PdGains& gains, const Eigen::VectorXd& kp_floor);

/// The plants a job's passes see at one posture: `mass` (n × n, armature included) with the
/// nominal `damping` and, when mismatch.viscous is set, with the true plant's.
std::vector<LoopPlant> make_job_plants(const JobConfig& config, const Eigen::MatrixXd& mass, const Eigen::VectorXd& damping);

/// The job's steps: explicit values as set, "auto" ones as calc_stable_steps picks them with
/// kStepMargin for every plant and controller (a job that collects nothing and runs open loop
/// needs only the integrator).
StepChoice calc_job_steps(const JobConfig& config, const std::vector<LoopPlant>& plants, const std::vector<JobController>& controllers);

/// One problem of the steps: the key to change and the message (the numbers and a value that works).
struct StepProblem {
  std::string key;
  std::string message;
};

/// The problems of `config`'s steps on `plants` (at `where`, for messages: the start posture, or
/// the postures along the job's trajectories): an explicit pd_substeps or
/// integrator_steps_per_tick that the criterion calls unstable (without margin), or "auto" finding
/// no stable steps within the keys' ranges. `joint_numbers`: 1-based, for messages.
std::vector<StepProblem> check_job_steps(const JobConfig& config, const std::vector<LoopPlant>& plants,
                                         const std::vector<JobController>& controllers, const std::vector<int>& joint_numbers,
                                         const std::string& where = "the start posture");

/// A job's plants and controllers at the start posture, from the model's facts.
struct StartPostureLoops {
  std::vector<LoopPlant> plants;
  std::vector<JobController> controllers;
  std::vector<int> joint_numbers;  ///< 1-based
};

/// The loops of `config` at the start posture of the model `facts` describe (its mass matrix
/// restricted to the active joints, armature × armature_scale); empty when the facts carry no
/// mass matrix or the gains cannot be placed (mis-sized or negative: their keys report that).
std::optional<StartPostureLoops> make_start_posture_loops(const JobConfig& config, const ModelFacts& facts);

/// check_job_steps's results by everything they depend on (the plants, the controllers with
/// their scale keys, the joint numbers, dt, the integrator and the explicit steps, the posture's
/// name), for the validation of many jobs against one model (ModelFacts::step_checks): a sweep's
/// jobs mostly differ in keys the steps do not read (learning.lwpr.init_D), and the
/// eigen-analyses of calc_stable_steps then run once per distinct loop instead of once per job.
/// The same problems as check_job_steps, bit for bit (tests/engine/experiment/job_steps_test.cpp).
/// Thread-safe; holds at most kCapacity results, then starts over.
class StepCheckMemo {
 public:
  static constexpr std::size_t kCapacity = 4096;

  std::vector<StepProblem> check(const JobConfig& config, const StartPostureLoops& loops,
                                 const std::string& where = "the start posture");
  /// How many checks ran check_job_steps rather than reusing a result.
  std::size_t computed() const;

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::vector<StepProblem>> results_;
  std::size_t computed_ = 0;
};

/// The steps a job of `config` runs with as judged at the start posture (before its
/// trajectories add postures): what `armfarm model info` shows for the default job.
/// found = false when `facts` carry no mass matrix.
StepChoice calc_start_posture_steps(const JobConfig& config, const ModelFacts& facts);

}  // namespace armfarm
