#include "engine/experiment/job_setup.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// 1-based joint numbers → 0-based indices into movable_joints(); empty = every movable joint.
std::vector<int> resolve_joint_numbers(const ArmModel& model, const std::vector<int>& numbers) {
  const int movable = static_cast<int>(model.movable_joints().size());
  std::vector<int> result;
  if (numbers.empty()) {
    for (int i = 1; i <= movable; ++i) result.push_back(i);
    return result;
  }
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (numbers[i] < 1 || numbers[i] > movable) {
      throw std::invalid_argument("active_joints[" + std::to_string(i) + "]: joint " + std::to_string(numbers[i]) +
                                  " does not exist; " + model.name + " has joints 1.." + std::to_string(movable));
    }
    if (std::count(numbers.begin(), numbers.end(), numbers[i]) > 1) {
      throw std::invalid_argument("active_joints[" + std::to_string(i) + "]: joint " + std::to_string(numbers[i]) +
                                  " is listed twice");
    }
    result.push_back(numbers[i]);
  }
  return result;
}

std::vector<int> make_indices(const std::vector<int>& numbers) {
  std::vector<int> indices;
  for (int number : numbers) indices.push_back(number - 1);
  return indices;
}

}  // namespace

JobSetup::JobSetup(const ArmModel& model, const JobConfig& config)
    : model_(model),
      config_(config),
      joint_numbers_(resolve_joint_numbers(model, config.active_joints)),
      active_indices_(make_indices(joint_numbers_)),
      nominal_(model, active_indices_),
      n_(nominal_.dof()) {
  validate();
  gains_ = make_pd_gains(config.control, nominal_);
  if (config.mismatch.payload.mass > 0.0) {
    true_dynamics_ = std::make_unique<ArmDynamics>(model, active_indices_, config.mismatch.payload);
  }
  nominal_viscous_ = nominal_.viscous_damping();
  nominal_coulomb_ = nominal_.coulomb_friction();
  true_viscous_ = config.mismatch.viscous.size() ? expand_per_joint(config.mismatch.viscous, n_, 0.0, "mismatch.viscous")
                                                 : nominal_viscous_;
  true_coulomb_ = config.mismatch.coulomb.size() ? expand_per_joint(config.mismatch.coulomb, n_, 0.0, "mismatch.coulomb")
                                                 : nominal_coulomb_;
}

void JobSetup::validate() const {
  if (!(config_.dt > 0.0) || config_.dt > 1.0) throw std::invalid_argument("dt: must be in (0, 1] s");
  if (!(config_.integrator_accuracy > 0.0) || config_.integrator_accuracy >= 1.0) {
    throw std::invalid_argument("integrator_accuracy: must be in (0, 1)");
  }
  if (!(config_.control.gain_scale >= 0.0)) throw std::invalid_argument("control.gain_scale: must not be negative");
  if (!(config_.control.bandwidth > 0.0)) throw std::invalid_argument("control.bandwidth: must be positive");
  if (!(config_.control.damping_ratio >= 0.0)) throw std::invalid_argument("control.damping_ratio: must not be negative");
  const LearningConfig& learning = config_.learning;
  if (!(learning.train_fraction > 0.0 && learning.train_fraction <= 1.0)) {
    throw std::invalid_argument("learning.train_fraction: must be in (0, 1]");
  }
  if (learning.epochs < 1) throw std::invalid_argument("learning.epochs: must be at least 1");
  if (learning.collect_repeats < 1) throw std::invalid_argument("learning.collect_repeats: must be at least 1");
  if (!(learning.collect_gain_scale >= 0.0)) throw std::invalid_argument("learning.collect_gain_scale: must not be negative");
  if (!(learning.collect_start_spread >= 0.0)) throw std::invalid_argument("learning.collect_start_spread: must not be negative");
  if (!(learning.collect_noise_q >= 0.0)) throw std::invalid_argument("learning.collect_noise_q: must not be negative");
  if (!(learning.collect_noise_qd >= 0.0)) throw std::invalid_argument("learning.collect_noise_qd: must not be negative");
  for (std::size_t i = 0; i < learning.heldout_checkpoints.size(); ++i) {
    if (learning.heldout_checkpoints[i] < 0 ||
        (i > 0 && learning.heldout_checkpoints[i] <= learning.heldout_checkpoints[i - 1])) {
      throw std::invalid_argument("learning.heldout_checkpoints[" + std::to_string(i) +
                                  "]: checkpoints must be non-negative and increasing");
    }
  }
  if (learning.heldout_segments < 0) throw std::invalid_argument("learning.heldout_segments: must not be negative");
  if (!(learning.heldout_amplitude_scale > 0.0)) throw std::invalid_argument("learning.heldout_amplitude_scale: must be positive");
  if (!std::isfinite(learning.heldout_phase_step)) throw std::invalid_argument("learning.heldout_phase_step: must be finite");
  if (!(learning.heldout_recorded_fraction > 0.0 && learning.heldout_recorded_fraction < 1.0)) {
    throw std::invalid_argument("learning.heldout_recorded_fraction: must be in (0, 1)");
  }
  if (config_.control.feed_forward == FeedForwardSource::learner && config_.control.mode != ControlMode::feedback &&
      learning.mode == LearningMode::none) {
    throw std::invalid_argument("learning.mode: is \"none\" but control.feed_forward is \"learner\"");
  }
  if (config_.recording.every < 1) throw std::invalid_argument("recording.every: must be at least 1");
  const DivergenceConfig& divergence = config_.divergence;
  if (!(divergence.max_tracking_error > 0.0)) throw std::invalid_argument("divergence.max_tracking_error: must be positive");
  if (!(divergence.max_error_duration >= 0.0)) throw std::invalid_argument("divergence.max_error_duration: must not be negative");
  if (!(divergence.velocity_limit_factor > 0.0)) throw std::invalid_argument("divergence.velocity_limit_factor: must be positive");
  if (config_.mismatch.payload.mass < 0.0) throw std::invalid_argument("mismatch.payload.mass: must not be negative");
}

ArmSimulation JobSetup::make_plant() const {
  ArmSimulationOptions options;
  options.active_joints = active_indices_;
  options.integrator = config_.integrator;
  options.accuracy = config_.integrator_accuracy;
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
  Eigen::VectorXd torque = (mismatch_present && true_dynamics_) ? true_dynamics_->calc_inverse_dynamics(q, qd, qdd)
                                                                : nominal_.calc_inverse_dynamics(q, qd, qdd);
  const Eigen::VectorXd& viscous = mismatch_present ? true_viscous_ : nominal_viscous_;
  const Eigen::VectorXd& coulomb = mismatch_present ? true_coulomb_ : nominal_coulomb_;
  const double velocity_scale = ArmSimulationOptions{}.coulomb_velocity_scale;
  for (int j = 0; j < n_; ++j) torque[j] += viscous[j] * qd[j] + coulomb[j] * std::tanh(qd[j] / velocity_scale);
  return torque;
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
