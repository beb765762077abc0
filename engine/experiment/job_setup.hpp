#pragma once
// What every phase of one experiment job shares: the active joints, the nominal model the
// controller and the analytic feed-forward know, the PD gains, and the true plant (the nominal
// model plus the configured mismatch) that the learners are scored against.
#include "engine/control/composite_controller.hpp"
#include "engine/control/pd_gains.hpp"
#include "engine/control/step_stability.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_steps.hpp"
#include "engine/experiment/pass_statistics.hpp"
#include "engine/kinematics/serial_chain.hpp"
#include "engine/model/arm_model.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace armfarm {

class JobSetup {
 public:
  /// Resolves joints and gains of a configuration that validate() (job_config_validation.hpp)
  /// accepted; throws std::invalid_argument naming the field for what only the model can tell.
  JobSetup(const ArmModel& model, const JobConfig& config);
  JobSetup(const JobSetup&) = delete;  // the dynamics refer to the job's model copy
  JobSetup& operator=(const JobSetup&) = delete;

  const ArmModel& model() const { return model_; }
  const JobConfig& config() const { return config_; }
  const std::vector<int>& joint_numbers() const { return joint_numbers_; }  ///< 1-based
  int dof() const { return n_; }
  ArmDynamics& nominal() { return nominal_; }  ///< scratch state inside: one per job
  /// The end effector's kinematic chain on the job's joints (world-frame position in a
  /// microsecond, equal to nominal().calc_end_effector_position to 1e-12; the statistics use it).
  const SerialChain& end_effector() const { return end_effector_; }
  /// The full-scale gains (gain_scale not applied): as configured, or placed by mass_bandwidth on
  /// the start posture's mass-matrix diagonal and, after fit_to_trajectories, on
  /// calc_placement_inertia over the postures along the job's trajectories (pd_gains.hpp).
  const PdGains& gains() const { return gains_; }
  /// The kp floor after any gain scale (n, N·m/rad): kGravityStiffnessMargin × the gravity
  /// stiffness's row sums over the start posture and, after fit_to_trajectories, the postures
  /// along the job's trajectories (pd_gains.hpp); zeros when has_placed_gains() is false.
  const Eigen::VectorXd& kp_floor() const { return kp_floor_; }
  /// The full-scale gains a controller at gain scale `scale` runs (× scale): gains() with the
  /// kp floor applied (calc_floored_gains).
  PdGains gains_at(double scale) const { return calc_floored_gains(gains_, kp_floor_, scale); }
  /// The PD periods per tick and RK4 steps per PD period the job's plants run with: explicit
  /// values as configured, "auto" ones chosen by the step-stability criterion (job_steps.hpp) at
  /// the start posture and, after fit_to_trajectories, at postures along the job's trajectories.
  int pd_substeps() const { return steps_.pd_substeps; }
  int integrator_steps() const { return steps_.integrator_steps; }
  /// Both, and whether the criterion found them stable (StepChoice::found).
  const StepChoice& steps() const { return steps_; }
  /// When the criterion finds the steps unstable over the postures fit_to_trajectories judged
  /// (an explicit value, with the gains placed for those postures, or "auto" finding none): the
  /// key and the message with the fix (check_job_steps); empty otherwise.
  const std::vector<StepProblem>& step_problems() const { return step_problems_; }
  /// Places the gains and the kp floor and chooses the "auto" steps again over the start posture and up to
  /// kStepPostures postures spread along each of `trajectories` (where the mass matrix and the
  /// gravity stiffness differ from the start's). Call before make_plant() and make_controller().
  void fit_to_trajectories(const std::vector<const JointTrajectory*>& trajectories);
  /// The steps the criterion picks for `controller`'s gains on this job's plant at posture `q`
  /// (a diverged pass's advice, divergence_advice.hpp).
  StepChoice calc_steps_at(const Eigen::VectorXd& q, const CompositeController& controller);
  /// The job's controller: control.mode with the gains at control.gain_scale (kd per keep_damping_ratio).
  CompositeController make_controller();
  /// The nMSE floors (kNmseStdFloorFraction of each joint's position range, 2π when unlimited;
  /// of its torque range 2·effort limit; of the end effector's 2·reach).
  ErrorFloors make_error_floors() const;

  /// Whether the plant differs from the nominal model from the start of every pass
  /// (mismatch.start_time ≤ 0) rather than from start_time into the evaluation passes.
  bool mismatch_from_start() const { return config_.mismatch.start_time <= 0.0; }
  /// Whether any mismatch (payload, friction) is configured at all.
  bool has_mismatch() const {
    return config_.mismatch.payload.mass > 0.0 || config_.mismatch.viscous.size() || config_.mismatch.coulomb.size();
  }
  /// A fresh plant at the nominal model, with the mismatch in place when mismatch_from_start().
  ArmSimulation make_plant() const;
  void apply_mismatch(ArmSimulation& plant) const;
  void remove_mismatch(ArmSimulation& plant) const;

  /// The torque (n) the true plant needs for (q, q̇, q̈): rigid body (with the payload once the
  /// mismatch is present) plus its joint friction — the ground truth of id_nmse.
  Eigen::VectorXd calc_true_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   bool mismatch_present);

 private:
  ArmModel model_;  ///< the job's copy: armature × simulation.armature_scale
  const JobConfig& config_;
  std::vector<int> joint_numbers_;
  std::vector<int> active_indices_;
  ArmDynamics nominal_;
  SerialChain end_effector_;
  int n_;
  PdGains gains_;
  Eigen::VectorXd kp_floor_;
  StepChoice steps_;
  std::vector<StepProblem> step_problems_;
  std::unique_ptr<ArmDynamics> true_dynamics_;
  Eigen::VectorXd true_viscous_, true_coulomb_, nominal_viscous_, nominal_coulomb_;
  double reach_ = 0.0;  ///< m, the arm's reach
};

/// Postures per trajectory at which JobSetup::fit_to_trajectories places the kp floor and checks the step criterion.
inline constexpr int kStepPostures = 20;

/// Per learner input (q, q̇, q̈ of each active joint, 3n): its standard deviation along the
/// desired trajectory (1 where it does not vary), the scale LWPR normalises its inputs by.
Eigen::VectorXd calc_trajectory_input_scale(const JointTrajectory& trajectory);

}  // namespace armfarm
