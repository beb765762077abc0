#include "engine/experiment/job_steps.hpp"

#include "engine/control/composite_controller.hpp"

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

bool is_fixed_step(const JobConfig& config) { return config.simulation.integrator == IntegratorKind::runge_kutta_4; }

/// The explicit values (0 = "auto"); adaptive integrators take S = 1 (they do not use it).
int explicit_pd(const JobConfig& config) { return config.simulation.pd_substeps.value_or(0); }
int explicit_integrator(const JobConfig& config) {
  return is_fixed_step(config) ? config.simulation.integrator_steps_per_tick.value_or(0) : 1;
}

std::vector<LoopGains> gains_of(const std::vector<JobController>& controllers) {
  std::vector<LoopGains> gains;
  for (const JobController& controller : controllers) gains.push_back(controller.gains);
  return gains;
}

/// The first (plant, controller) the steps are unstable for, without margin.
struct Failure {
  bool found = false;
  LoopStability stability;
  const JobController* controller = nullptr;
};

Failure find_failure(const JobConfig& config, const std::vector<LoopPlant>& plants, const std::vector<JobController>& controllers,
                     int pd, int integrator) {
  const LoopSteps steps{config.simulation.dt, pd, integrator, is_fixed_step(config)};
  for (const LoopPlant& plant : plants) {
    if (controllers.empty()) {
      const LoopStability stability = calc_loop_stability(plant, nullptr, steps);
      if (!stability.stable()) return Failure{true, stability, nullptr};
    }
    for (const JobController& controller : controllers) {
      const LoopStability stability = calc_loop_stability(plant, &controller.gains, steps);
      if (!stability.stable()) return Failure{true, stability, &controller};
    }
  }
  return {};
}

/// "the PD loop is unstable on joint 7 at the start posture (…numbers…)" or the integrator's.
std::string describe_failure(const JobConfig& config, const Failure& failure, int pd, int integrator, const std::vector<int>& joint_numbers,
                             const std::string& where) {
  const LoopStability& s = failure.stability;
  const int joint = joint_numbers.at(static_cast<std::size_t>(s.joint));
  const double period = config.simulation.dt / pd;
  if (!s.integrator_stable()) {
    return "runge_kutta_4 in steps of " + format_figure(period / integrator) + " s amplifies the passive decay of joint " +
           std::to_string(joint) + " at " + where + ": λ·h_i = " + format_figure(s.passive_step_ratio) +
           ", above RK4's bound " + format_figure(kRk4RealBound) + " (λ the fastest rate of M⁻¹B; joint " + std::to_string(joint) +
           " alone: b·h_i/M = " + format_figure(s.damping_ratio) + " with b = " +
           format_figure(s.damping_ratio * s.inertia * integrator / period) + " N·m·s/rad, M = " + format_figure(s.inertia) +
           " kg·m² with armature)";
  }
  const JobController& controller = *failure.controller;
  const double kd = s.kd_ratio * s.inertia / period, kp = s.kp_ratio * s.inertia / (period * period);
  return "the sampled PD loop is unstable on joint " + std::to_string(joint) + " at " + where + ": PD period h = " +
         format_figure(period) + " s, kd·h/M = " + format_figure(s.kd_ratio) + " (bound 2), kp·h²/M = " + format_figure(s.kp_ratio) +
         " (bound 2·kd·h/M = " + format_figure(2.0 * s.kd_ratio) + "), with M = " + format_figure(s.inertia) +
         " kg·m² (mass-matrix diagonal, armature included), kd = " + format_figure(kd) + " N·m·s/rad and kp = " + format_figure(kp) +
         " N·m/rad after " + controller.scale_key + " " + format_figure(controller.scale) +
         "; coupled through the mass matrix, the fastest mode has kd·h/M = " + format_figure(s.modal_kd_ratio) +
         " (λ_max(M⁻¹Kd)·h), and the error grows ×" + format_figure(s.spectral_radius) + " per PD period";
}

}  // namespace

std::string format_figure(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

double calc_collect_gain_scale(const JobConfig& config) {
  return config.learning.collect_gain_scale.value_or(config.control.gain_scale);
}

bool has_collection_passes(const JobConfig& config) {
  const LearningMode mode = config.learning.mode;
  return mode == LearningMode::batch || (mode != LearningMode::none && config.learning.heldout);
}

std::vector<JobController> make_job_controllers(const JobConfig& config, const PdGains& gains, const Eigen::VectorXd& kp_floor) {
  const ControlConfig& control = config.control;
  const auto make = [&](double scale, const char* key) {
    const double kd_scale = calc_kd_scale(scale, control.keep_damping_ratio);
    const PdGains floored = calc_floored_gains(gains, kp_floor, scale);
    return JobController{LoopGains{floored.kp * scale, floored.kd * kd_scale}, key, scale};
  };
  std::vector<JobController> controllers;
  if (control.mode != ControlMode::open_loop) controllers.push_back(make(control.gain_scale, "control.gain_scale"));
  const double collect = calc_collect_gain_scale(config);
  if (has_collection_passes(config) && (controllers.empty() || collect != control.gain_scale)) {
    controllers.push_back(make(collect, "learning.collect_gain_scale"));
  }
  return controllers;
}

std::vector<LoopPlant> make_job_plants(const JobConfig& config, const Eigen::MatrixXd& mass, const Eigen::VectorXd& damping) {
  std::vector<LoopPlant> plants{LoopPlant{mass, damping}};
  const Eigen::VectorXd& viscous = config.mismatch.viscous;
  if (viscous.size() == 1) plants.push_back(LoopPlant{mass, Eigen::VectorXd::Constant(damping.size(), viscous[0])});
  if (viscous.size() > 1 && viscous.size() == damping.size()) plants.push_back(LoopPlant{mass, viscous});
  return plants;
}

StepChoice calc_job_steps(const JobConfig& config, const std::vector<LoopPlant>& plants, const std::vector<JobController>& controllers) {
  const std::vector<LoopGains> gains = gains_of(controllers);
  const double dt = config.simulation.dt;
  const StepChoice choice =
      calc_stable_steps(plants, gains, dt, is_fixed_step(config), explicit_pd(config), explicit_integrator(config), kStepMargin);
  if (choice.found) return choice;
  // Where the keys' ranges allow no margin, stable without it.
  const StepChoice plain = calc_stable_steps(plants, gains, dt, is_fixed_step(config), explicit_pd(config), explicit_integrator(config), 1.0);
  return plain.found ? plain : choice;
}

std::vector<StepProblem> check_job_steps(const JobConfig& config, const std::vector<LoopPlant>& plants,
                                         const std::vector<JobController>& controllers, const std::vector<int>& joint_numbers,
                                         const std::string& where) {
  const StepChoice run = calc_job_steps(config, plants, controllers);
  if (run.found) return {};
  const int pd = explicit_pd(config), integrator = explicit_integrator(config);
  const Failure failure = find_failure(config, plants, controllers, run.pd_substeps, run.integrator_steps);
  if (!failure.found) return {};
  const bool integrator_fails = !failure.stability.integrator_stable();
  // The key to blame: the integrator's when its decay is amplified, else the PD period's.
  const std::string key = integrator_fails && is_fixed_step(config) ? "integrator_steps_per_tick" : "pd_substeps";
  const bool blamed_explicit = key == "pd_substeps" ? pd > 0 : config.simulation.integrator_steps_per_tick.has_value();
  const int value = key == "pd_substeps" ? run.pd_substeps : run.integrator_steps;
  std::string message = (blamed_explicit ? std::to_string(value) + " is unstable: " : std::string("\"auto\" finds no stable value up to ") +
                                                                                         std::to_string(value) + ": ") +
                        describe_failure(config, failure, run.pd_substeps, run.integrator_steps, joint_numbers, where);
  // The fix: the blamed key chosen by the criterion, the other held when it is explicit.
  const std::vector<LoopGains> gains = gains_of(controllers);
  const bool fixed = is_fixed_step(config);
  StepChoice fix = calc_stable_steps(plants, gains, config.simulation.dt, fixed, key == "pd_substeps" ? 0 : pd,
                                     key == "pd_substeps" ? integrator : 0, kStepMargin);
  if (fix.found && blamed_explicit) {
    message += "; " + key + " " + std::to_string(key == "pd_substeps" ? fix.pd_substeps : fix.integrator_steps) +
               " is stable with the criterion's margin (or \"auto\")";
    return {StepProblem{key, message}};
  }
  fix = calc_stable_steps(plants, gains, config.simulation.dt, fixed, 0, 0, kStepMargin);
  if (fix.found) {
    message += "; pd_substeps " + std::to_string(fix.pd_substeps) +
               (fixed ? " with integrator_steps_per_tick " + std::to_string(fix.integrator_steps) : std::string()) +
               " are stable with the criterion's margin (or \"auto\" for both)";
  } else {
    message += "; no steps within the keys' ranges are: lower the gains (control.gain_scale, control.kp, control.kd) or dt";
  }
  return {StepProblem{key, message}};
}

std::optional<StartPostureLoops> make_start_posture_loops(const JobConfig& config, const ModelFacts& facts) {
  const int movable = facts.movable_joints;
  if (facts.rigid_mass.rows() != movable || facts.armature.size() != movable || facts.damping.size() != movable) return std::nullopt;
  StartPostureLoops loops;
  loops.joint_numbers = config.active_joints;
  if (loops.joint_numbers.empty()) {
    for (int j = 1; j <= movable; ++j) loops.joint_numbers.push_back(j);
  }
  const std::vector<int>& numbers = loops.joint_numbers;
  const auto n = static_cast<Eigen::Index>(numbers.size());
  for (int number : numbers) {
    if (number < 1 || number > movable) return std::nullopt;
  }
  if (n == 0) return std::nullopt;
  // The configured start posture, when it differs from the file's (a check of its own reports a bad one).
  Eigen::MatrixXd rigid = facts.rigid_mass;
  const Eigen::VectorXd& posture = config.start_posture;
  if (posture.size() != 0) {
    if (posture.size() != movable || !facts.rigid_mass_at) return std::nullopt;
    bool same = true;
    for (int j = 0; j < movable && same; ++j) same = posture[j] == facts.start_positions[static_cast<std::size_t>(j)];
    if (!same) rigid = facts.rigid_mass_at(posture);
  }
  // The gravity stiffness at the same posture, for the default gains' kp floor.
  std::vector<Eigen::MatrixXd> stiffness;
  if (has_placed_gains(config.control) && facts.gravity_stiffness_at &&
      facts.start_positions.size() == static_cast<std::size_t>(movable)) {
    const Eigen::VectorXd start = posture.size() != 0 ? posture
                                                     : Eigen::Map<const Eigen::VectorXd>(facts.start_positions.data(), movable).eval();
    const Eigen::MatrixXd all = facts.gravity_stiffness_at(start);
    Eigen::MatrixXd active(n, n);
    for (Eigen::Index r = 0; r < n; ++r) {
      for (Eigen::Index c = 0; c < n; ++c) active(r, c) = all(numbers[r] - 1, numbers[c] - 1);
    }
    stiffness.push_back(active);
  }
  Eigen::MatrixXd mass(n, n);
  Eigen::VectorXd damping(n);
  for (Eigen::Index r = 0; r < n; ++r) {
    for (Eigen::Index c = 0; c < n; ++c) mass(r, c) = rigid(numbers[r] - 1, numbers[c] - 1);
    mass(r, r) += config.simulation.armature_scale * facts.armature[numbers[r] - 1];
    damping[r] = facts.damping[numbers[r] - 1];
  }
  PdGains gains;
  try {
    gains = calc_pd_gains(config.control, mass.diagonal(), numbers);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  loops.plants = make_job_plants(config, mass, damping);
  loops.controllers = make_job_controllers(config, gains, calc_gravity_kp_floor(stiffness, static_cast<int>(n)));
  return loops;
}

namespace {

// The bytes of each value, in order: the memo's key (equal keys, equal inputs, bit for bit).
class KeyWriter {
 public:
  template <typename T>
  void add(const T& value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    key_.append(bytes, sizeof(T));
  }
  void add(const Eigen::MatrixXd& m) {
    add(m.rows());
    add(m.cols());
    key_.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * static_cast<std::size_t>(m.size()));
  }
  void add(const Eigen::VectorXd& v) {
    add(v.size());
    key_.append(reinterpret_cast<const char*>(v.data()), sizeof(double) * static_cast<std::size_t>(v.size()));
  }
  void add(const std::string& text) {
    add(text.size());
    key_ += text;
  }
  std::string take() { return std::move(key_); }

 private:
  std::string key_;
};

// Everything check_job_steps reads of its arguments.
std::string make_step_check_key(const JobConfig& config, const StartPostureLoops& loops, const std::string& where) {
  KeyWriter key;
  const SimulationConfig& simulation = config.simulation;
  key.add(simulation.dt);
  key.add(static_cast<int>(simulation.integrator));
  key.add(simulation.pd_substeps.has_value());
  key.add(simulation.pd_substeps.value_or(0));
  key.add(simulation.integrator_steps_per_tick.has_value());
  key.add(simulation.integrator_steps_per_tick.value_or(0));
  key.add(loops.joint_numbers.size());
  for (int number : loops.joint_numbers) key.add(number);
  key.add(loops.plants.size());
  for (const LoopPlant& plant : loops.plants) {
    key.add(plant.mass);
    key.add(plant.damping);
  }
  key.add(loops.controllers.size());
  for (const JobController& controller : loops.controllers) {
    key.add(controller.gains.kp);
    key.add(controller.gains.kd);
    key.add(controller.scale_key);
    key.add(controller.scale);
  }
  key.add(where);
  return key.take();
}

}  // namespace

std::vector<StepProblem> StepCheckMemo::check(const JobConfig& config, const StartPostureLoops& loops, const std::string& where) {
  std::string key = make_step_check_key(config, loops, where);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto found = results_.find(key);
    if (found != results_.end()) return found->second;
  }
  // Checked outside the lock: other threads' checks of other loops go on meanwhile.
  std::vector<StepProblem> problems = check_job_steps(config, loops.plants, loops.controllers, loops.joint_numbers, where);
  std::lock_guard<std::mutex> lock(mutex_);
  ++computed_;
  if (results_.size() >= kCapacity) results_.clear();
  results_.emplace(std::move(key), problems);
  return problems;
}

std::size_t StepCheckMemo::computed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return computed_;
}

StepChoice calc_start_posture_steps(const JobConfig& config, const ModelFacts& facts) {
  const std::optional<StartPostureLoops> loops = make_start_posture_loops(config, facts);
  if (!loops) return StepChoice{0, 0, false};
  return calc_job_steps(config, loops->plants, loops->controllers);
}

}  // namespace armfarm
