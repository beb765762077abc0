#include "engine/experiment/job_setup.hpp"

#include "engine/experiment/job_steps.hpp"
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/nominal_inverse_dynamics.hpp"
#include "engine/model/arm_reach.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// 1-based joint numbers (validate() checked them); every movable joint for an empty list.
std::vector<int> resolve_joint_numbers(const ArmModel& model, const std::vector<int>& numbers) {
  if (!numbers.empty()) return numbers;
  std::vector<int> result;
  for (int i = 1; i <= static_cast<int>(model.movable_joints().size()); ++i) result.push_back(i);
  return result;
}

ArmModel scale_armature(const ArmModel& model, double scale) {
  ArmModel scaled = model;
  for (Joint& joint : scaled.joints) joint.armature *= scale;
  return scaled;
}

std::vector<int> make_indices(const std::vector<int>& numbers) {
  std::vector<int> indices;
  for (int number : numbers) indices.push_back(number - 1);
  return indices;
}

}  // namespace

JobSetup::JobSetup(const ArmModel& model, const JobConfig& config)
    : model_(scale_armature(model, config.simulation.armature_scale)),
      config_(config),
      joint_numbers_(resolve_joint_numbers(model_, config.active_joints)),
      active_indices_(make_indices(joint_numbers_)),
      nominal_(model_, active_indices_),
      end_effector_(make_end_effector_chain(nominal_)),
      n_(nominal_.dof()) {
  gains_ = make_pd_gains(config.control, nominal_, joint_numbers_);
  fit_to_trajectories({});
  reach_ = calc_reach(model_);
  if (config.mismatch.payload.mass > 0.0) {
    true_dynamics_ = std::make_unique<ArmDynamics>(model_, active_indices_, config.mismatch.payload);
  }
  nominal_viscous_ = nominal_.viscous_damping();
  nominal_coulomb_ = nominal_.coulomb_friction();
  true_viscous_ = config.mismatch.viscous.size() ? expand_per_joint(config.mismatch.viscous, n_, 0.0, "mismatch.viscous")
                                                 : nominal_viscous_;
  true_coulomb_ = config.mismatch.coulomb.size() ? expand_per_joint(config.mismatch.coulomb, n_, 0.0, "mismatch.coulomb")
                                                 : nominal_coulomb_;
}

void JobSetup::fit_to_trajectories(const std::vector<const JointTrajectory*>& trajectories) {
  std::vector<Eigen::VectorXd> postures{nominal_.start_positions()};
  for (const JointTrajectory* trajectory : trajectories) {
    const int size = trajectory ? trajectory->size() : 0;
    for (int i = 0; i < std::min(size, kStepPostures); ++i) {
      const int row = static_cast<int>((static_cast<long long>(i) * size) / std::min(size, kStepPostures));
      postures.push_back(trajectory->q.row(row).transpose());
    }
  }
  const Eigen::VectorXd damping = nominal_.viscous_damping();
  std::vector<LoopPlant> plants;
  std::vector<Eigen::MatrixXd> stiffness;
  Eigen::VectorXd max_inertia = Eigen::VectorXd::Zero(n_);
  for (const Eigen::VectorXd& q : postures) {
    const Eigen::MatrixXd mass = nominal_.calc_mass_matrix(q);
    max_inertia = max_inertia.cwiseMax(mass.diagonal());
    for (LoopPlant& plant : make_job_plants(config_, mass, damping)) plants.push_back(std::move(plant));
    if (has_placed_gains(config_.control)) stiffness.push_back(make_gravity_stiffness(nominal_, q));
  }
  if (has_placed_gains(config_.control)) {
    // Placed on the start posture's diagonal, raised where the postures visited carry far more.
    const Eigen::VectorXd start_inertia = plants.front().mass.diagonal();
    gains_ = calc_pd_gains(config_.control, calc_placement_inertia(start_inertia, max_inertia), joint_numbers_);
  }
  kp_floor_ = calc_gravity_kp_floor(stiffness, n_);
  const std::vector<JobController> controllers = make_job_controllers(config_, gains_, kp_floor_);
  steps_ = calc_job_steps(config_, plants, controllers);
  step_problems_.clear();
  if (!steps_.found) {
    step_problems_ = check_job_steps(config_, plants, controllers, joint_numbers_,
                                     trajectories.empty() ? "the start posture" : "a posture along the job's trajectories");
  }
}

StepChoice JobSetup::calc_steps_at(const Eigen::VectorXd& q, const CompositeController& controller) {
  const Eigen::VectorXd damping = nominal_.viscous_damping();
  const std::vector<LoopPlant> plants = make_job_plants(config_, nominal_.calc_mass_matrix(q), damping);
  const std::vector<LoopGains> gains{LoopGains{controller.kp(), controller.kd()}};
  return calc_stable_steps(plants, gains, config_.simulation.dt, config_.simulation.integrator == IntegratorKind::runge_kutta_4, 0, 0);
}

CompositeController JobSetup::make_controller() {
  const ControlConfig& control = config_.control;
  return CompositeController(control.mode, gains_at(control.gain_scale), control.gain_scale, calc_kd_scale(control.gain_scale, control.keep_damping_ratio),
                             nominal_.effort_limits(), control.limit_torque);
}

ErrorFloors JobSetup::make_error_floors() const {
  ErrorFloors floors;
  floors.angle.resize(n_);
  floors.torque.resize(n_);
  const Eigen::VectorXd lower = nominal_.lower_limits(), upper = nominal_.upper_limits(), limits = nominal_.effort_limits();
  for (int j = 0; j < n_; ++j) {
    const double range = std::isfinite(upper[j] - lower[j]) ? upper[j] - lower[j] : 2.0 * M_PI;
    floors.angle[j] = kNmseStdFloorFraction * range;
    // Without an effort limit only exact constancy (numerical noise) is undefined.
    floors.torque[j] = std::isfinite(limits[j]) && limits[j] > 0.0 ? kNmseStdFloorFraction * 2.0 * limits[j] : 1e-12;
  }
  floors.task = Eigen::Vector3d::Constant(kNmseStdFloorFraction * 2.0 * reach_);
  return floors;
}

ArmSimulation JobSetup::make_plant() const {
  ArmSimulationOptions options;
  options.active_joints = active_indices_;
  options.integrator = config_.simulation.integrator;
  options.accuracy = config_.simulation.integrator_accuracy;
  options.steps_per_tick = steps_.integrator_steps;
  if (mismatch_from_start()) {
    options.payload = config_.mismatch.payload;
    if (config_.mismatch.viscous.size()) options.friction_override.viscous = true_viscous_;
    if (config_.mismatch.coulomb.size()) options.friction_override.coulomb = true_coulomb_;
  }
  return ArmSimulation(model_, options);
}

void JobSetup::apply_mismatch(ArmSimulation& plant) const {
  plant.set_payload(config_.mismatch.payload);
  JointFrictionOverride friction;
  if (config_.mismatch.viscous.size()) friction.viscous = true_viscous_;
  if (config_.mismatch.coulomb.size()) friction.coulomb = true_coulomb_;
  plant.set_friction_override(friction);
}

void JobSetup::remove_mismatch(ArmSimulation& plant) const {
  plant.set_payload(Payload{});
  plant.set_friction_override(JointFrictionOverride{});
}

Eigen::VectorXd JobSetup::calc_true_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                           bool mismatch_present) {
  ArmDynamics& dynamics = (mismatch_present && true_dynamics_) ? *true_dynamics_ : nominal_;
  return calc_inverse_dynamics_with_friction(dynamics, q, qd, qdd, mismatch_present ? true_viscous_ : nominal_viscous_,
                                             mismatch_present ? true_coulomb_ : nominal_coulomb_,
                                             ArmSimulationOptions{}.coulomb_velocity_scale);
}

Eigen::VectorXd calc_trajectory_input_scale(const JointTrajectory& trajectory) {
  const auto n = trajectory.q.cols();
  Eigen::VectorXd scale(3 * n);
  for (int block = 0; block < 3; ++block) {
    const Eigen::MatrixXd& signal = block == 0 ? trajectory.q : block == 1 ? trajectory.qd : trajectory.qdd;
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::VectorXd column = signal.col(j);
      const double mean = column.mean();
      const double deviation = std::sqrt((column.array() - mean).square().mean());
      scale[block * n + j] = deviation > 1e-6 ? deviation : 1.0;
    }
  }
  return scale;
}

}  // namespace armfarm
