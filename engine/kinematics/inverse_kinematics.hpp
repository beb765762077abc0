#pragma once
// Inverse kinematics of the end-effector point: damped least squares on the 3×n position
// Jacobian with a null-space term pulling towards a rest posture, within the joint limits.
// Iterating until the null-space step vanishes too makes the solution the posture closest to
// the rest posture on the target's self-motion manifold (locally), a function of the target
// alone: a closed path gives a closed joint path (no jump on return, no drift from small
// target oscillations, the two faults the thesis reports).
// Units: SI and radians; targets in the world frame.
#include "engine/kinematics/serial_chain.hpp"

#include <Eigen/Core>

namespace armfarm {

class ArmDynamics;

struct InverseKinematicsOptions {
  double damping = 1e-3;           ///< λ of (J Jᵀ + λ² I)⁻¹, m
  double null_space_gain = 0.5;    ///< share of the way to rest_posture taken per iteration (in the null space)
  double tolerance = 1e-6;         ///< m, required |x − target| ...
  double null_space_tolerance = 1e-8;  ///< rad, ... and null-space step norm to stop
  int max_iterations = 500;
  /// rad: when no joint moves by more than this in one iteration and the target is still
  /// missed, the iteration sits at a fixed point that is not a solution (the null-space pull
  /// balanced by a joint limit, or by the damping when there is no null space, as on a 3-DOF
  /// arm): it finishes on position alone at once instead of after max_iterations. Stopping
  /// early moves the result by at most max_iterations × this.
  double stall_step = 1e-12;
  double limit_margin = 0.05;      ///< rad kept away from each joint limit
};

struct InverseKinematicsResult {
  Eigen::VectorXd q;
  double error = 0.0;     ///< m, final |x(q) − target|
  int iterations = 0;
  bool converged = false;
};

/// Solves x(q) = target for the point of `chain` starting from `initial` (n_active), with the
/// null space pulling towards `rest_posture`, within the chain's joint limits. Deterministic;
/// the same inputs give the same q. Costs a few microseconds per iteration (7 DOF).
InverseKinematicsResult solve_inverse_kinematics(const SerialChain& chain, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options = {});

/// The same for the end effector of `dynamics`'s model and active joints (builds the chain on
/// every call; callers solving many targets build it once with make_end_effector_chain).
InverseKinematicsResult solve_inverse_kinematics(const ArmDynamics& dynamics, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options = {});

}  // namespace armfarm
