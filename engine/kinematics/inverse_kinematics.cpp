#include "engine/kinematics/inverse_kinematics.hpp"

#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace armfarm {

InverseKinematicsResult solve_inverse_kinematics(ArmDynamics& dynamics, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options) {
  const int n = dynamics.dof();
  const Eigen::VectorXd lower = dynamics.lower_limits().array() + options.limit_margin;
  const Eigen::VectorXd upper = dynamics.upper_limits().array() - options.limit_margin;
  InverseKinematicsResult result;
  result.q = initial.cwiseMax(lower).cwiseMin(upper);
  const double lambda_squared = options.damping * options.damping;
  for (result.iterations = 0; result.iterations < options.max_iterations; ++result.iterations) {
    const Eigen::Vector3d error = target - dynamics.calc_end_effector_position(result.q);
    result.error = error.norm();
    const Eigen::Matrix3Xd jacobian = dynamics.calc_end_effector_jacobian(result.q);
    // Damped least squares: J⁺ = Jᵀ (J Jᵀ + λ² I)⁻¹ stays bounded near singular postures.
    const Eigen::Matrix3d gram = jacobian * jacobian.transpose() + lambda_squared * Eigen::Matrix3d::Identity();
    const Eigen::MatrixXd pseudo_inverse = jacobian.transpose() * gram.ldlt().solve(Eigen::Matrix3d::Identity());
    const Eigen::MatrixXd null_projector = Eigen::MatrixXd::Identity(n, n) - pseudo_inverse * jacobian;
    const Eigen::VectorXd null_step = options.null_space_gain * null_projector * (rest_posture - result.q);
    if (result.error < options.tolerance && null_step.norm() < options.null_space_tolerance) {
      result.converged = true;
      break;
    }
    const Eigen::VectorXd previous = result.q;
    result.q = (result.q + pseudo_inverse * error + null_step).cwiseMax(lower).cwiseMin(upper);
    // At a joint limit the null-space pull can be blocked for good; stop once nothing moves.
    if (result.error < options.tolerance && (result.q - previous).norm() < options.null_space_tolerance) {
      result.converged = true;
      break;
    }
  }
  if (!result.converged) {
    // The null space did not settle (e.g. pulled against a limit): finish on position alone.
    InverseKinematicsOptions position_only = options;
    position_only.null_space_gain = 0.0;
    position_only.max_iterations = 50;
    for (int i = 0; i < position_only.max_iterations; ++i) {
      const Eigen::Vector3d error = target - dynamics.calc_end_effector_position(result.q);
      result.error = error.norm();
      if (result.error < options.tolerance) break;
      const Eigen::Matrix3Xd jacobian = dynamics.calc_end_effector_jacobian(result.q);
      const Eigen::Matrix3d gram = jacobian * jacobian.transpose() + lambda_squared * Eigen::Matrix3d::Identity();
      result.q = (result.q + jacobian.transpose() * gram.ldlt().solve(error)).cwiseMax(lower).cwiseMin(upper);
    }
    result.error = (target - dynamics.calc_end_effector_position(result.q)).norm();
    result.converged = result.error < options.tolerance;
  }
  return result;
}

}  // namespace armfarm
