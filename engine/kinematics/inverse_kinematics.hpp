#pragma once
// Inverse kinematics of the end-effector point: damped least squares on the 3×n position
// Jacobian with a null-space term pulling towards a rest posture, within the joint limits.
// Iterating until the null-space step vanishes too makes the solution the posture closest to
// the rest posture on the target's self-motion manifold (locally), a function of the target
// alone: a closed path gives a closed joint path (no jump on return, no drift from small
// target oscillations, the two faults the thesis reports).
// Units: SI and radians; targets in the world frame.
#include <Eigen/Core>

namespace armfarm {

class ArmDynamics;

struct InverseKinematicsOptions {
  double damping = 1e-3;           ///< λ of (J Jᵀ + λ² I)⁻¹, m
  double null_space_gain = 0.5;    ///< share of the way to rest_posture taken per iteration (in the null space)
  double tolerance = 1e-6;         ///< m, required |x − target| ...
  double null_space_tolerance = 1e-8;  ///< rad, ... and null-space step norm to stop
  int max_iterations = 500;
  double limit_margin = 0.05;      ///< rad kept away from each joint limit
};

struct InverseKinematicsResult {
  Eigen::VectorXd q;
  double error = 0.0;     ///< m, final |x(q) − target|
  int iterations = 0;
  bool converged = false;
};

/// Solves x(q) = target starting from `initial` (n_active), with the null space pulling
/// towards `rest_posture`. Deterministic; the same inputs give the same q.
InverseKinematicsResult solve_inverse_kinematics(ArmDynamics& dynamics, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options = {});

}  // namespace armfarm
