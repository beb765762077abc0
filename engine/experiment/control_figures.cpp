#include "engine/experiment/control_figures.hpp"

#include "engine/control/pd_gains.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/job_steps.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <exception>
#include <limits>

namespace armfarm {
namespace {

/// The steps, the gains and the kp floor over the job's trajectories, as run_experiment places
/// them (JobSetup::fit_to_trajectories).
struct TrajectoryFit {
  StepChoice steps;
  PdGains gains;
  Eigen::VectorXd kp_floor;
};
TrajectoryFit calc_trajectory_fit(const ArmModel& model, const JobConfig& config) {
  JobSetup setup(model, config);
  const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  setup.fit_to_trajectories({&trajectories.training, trajectories.heldout ? &*trajectories.heldout : nullptr});
  return {setup.steps(), setup.gains(), setup.kp_floor()};
}

}  // namespace

ControlFigures calc_control_figures(const ArmModel& model, const JobConfig& config) {
  std::vector<int> numbers = config.active_joints;
  if (numbers.empty()) {
    for (int i = 1; i <= static_cast<int>(model.movable_joints().size()); ++i) numbers.push_back(i);
  }
  std::vector<int> indices;
  for (int number : numbers) indices.push_back(number - 1);
  // As JobSetup builds the job's nominal model: the armature scaled.
  ArmModel scaled = model;
  for (Joint& joint : scaled.joints) joint.armature *= config.simulation.armature_scale;
  ArmDynamics dynamics(scaled, indices);
  const Eigen::VectorXd start = dynamics.start_positions();
  const Eigen::MatrixXd mass = dynamics.calc_mass_matrix(start);
  const Eigen::VectorXd damping = dynamics.viscous_damping();
  PdGains gains = make_pd_gains(config.control, dynamics, numbers);
  std::vector<Eigen::MatrixXd> stiffness;
  if (has_placed_gains(config.control)) stiffness.push_back(make_gravity_stiffness(dynamics, start));
  Eigen::VectorXd kp_floor = calc_gravity_kp_floor(stiffness, static_cast<int>(numbers.size()));

  // The steps: at the start posture, then over the trajectories where they can be built.
  ControlFigures figures;
  JobStepFigures& steps = figures.steps;
  steps.dt = config.simulation.dt;
  steps.fixed_step = config.simulation.integrator == IntegratorKind::runge_kutta_4;
  const std::vector<LoopPlant> plants = make_job_plants(config, mass, damping);
  const std::vector<JobController> controllers = make_job_controllers(config, gains, kp_floor);
  steps.at_start = calc_job_steps(config, plants, controllers);
  steps.run = steps.at_start;
  if (model.end_effector.link < 0) {
    steps.trajectory_problem = "no end effector chosen";  // a job cannot be set up without one
  } else {
    try {
      const TrajectoryFit fit = calc_trajectory_fit(model, config);
      steps.run = fit.steps;
      gains = fit.gains;
      kp_floor = fit.kp_floor;
    } catch (const std::exception& error) {
      steps.trajectory_problem = error.what();
    }
  }
  const double period = steps.dt / steps.run.pd_substeps, step = period / steps.run.integrator_steps;
  const std::vector<JobController> run_controllers = make_job_controllers(config, gains, kp_floor);
  if (!run_controllers.empty()) {
    const LoopStability stability = calc_loop_stability(
        plants.front(), &run_controllers.front().gains, LoopSteps{steps.dt, steps.run.pd_substeps, steps.run.integrator_steps, steps.fixed_step});
    steps.modal_kd_ratio = stability.modal_kd_ratio;
    steps.spectral_radius = stability.spectral_radius;
  }

  const double kp_scale = config.control.gain_scale;
  const double kd_scale = calc_kd_scale(config.control.gain_scale, config.control.keep_damping_ratio);
  const PdGains run_gains = calc_floored_gains(gains, kp_floor, kp_scale);  // as the job's controller runs them
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    JointControlFigures joint;
    joint.number = numbers[i];
    joint.start_position = start[j];
    joint.mass_diagonal = mass(j, j);
    joint.kp = run_gains.kp[j] * kp_scale;
    joint.kd = run_gains.kd[j] * kd_scale;
    joint.damping = damping[j];
    joint.kd_ratio = joint.kd * period / joint.mass_diagonal;
    joint.kp_ratio = joint.kp * period * period / joint.mass_diagonal;
    joint.damping_ratio = steps.fixed_step ? joint.damping * step / joint.mass_diagonal : std::numeric_limits<double>::quiet_NaN();
    figures.joints.push_back(joint);
  }
  return figures;
}

}  // namespace armfarm
