#include "engine/kinematics/inverse_kinematics.hpp"

#include "engine/kinematics/damped_gram.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// G = J Jᵀ + λ² I factored: by DampedGram up to its column limit (Eigen's bits, a quarter of the
/// instructions), by Eigen's product and LDLT beyond it.
class GramFactor {
 public:
  void compute(const Eigen::Matrix3Xd& jacobian, double lambda_squared) {
    small_ = jacobian.cols() <= DampedGram::kMaxColumns;
    if (small_) {
      damped_.factor(jacobian, lambda_squared);
      return;
    }
    gram_.noalias() = jacobian * jacobian.transpose();
    gram_.diagonal().array() += lambda_squared;
    ldlt_.compute(gram_);
  }
  Eigen::Vector3d solve(const Eigen::Vector3d& b) const { return small_ ? damped_.solve(b) : Eigen::Vector3d(ldlt_.solve(b)); }

 private:
  bool small_ = true;
  DampedGram damped_;
  Eigen::Matrix3d gram_;
  Eigen::LDLT<Eigen::Matrix3d> ldlt_;
};

}  // namespace

InverseKinematicsResult solve_inverse_kinematics(const SerialChain& chain, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options) {
  const int n = chain.dof();
  if (initial.size() != n || rest_posture.size() != n) {
    throw std::invalid_argument("inverse kinematics: expected " + std::to_string(n) + " joint angles in the start and rest postures");
  }
  const Eigen::VectorXd lower = chain.lower_limits().array() + options.limit_margin;
  const Eigen::VectorXd upper = chain.upper_limits().array() - options.limit_margin;
  InverseKinematicsResult result;
  result.q = initial.cwiseMax(lower).cwiseMin(upper);
  const double lambda_squared = options.damping * options.damping;
  // Work space for the iterations, sized once. J⁺ and the null projector I − J⁺J are never
  // formed: with G = J Jᵀ + λ² I, J⁺e = Jᵀ G⁻¹ e and (I − J⁺J) d = d − Jᵀ G⁻¹ (J d), O(n) each.
  Eigen::Vector3d position;
  Eigen::Matrix3Xd jacobian(3, n);
  Eigen::VectorXd to_rest(n), null_step(n), previous(n);
  GramFactor gram_factor;
  for (result.iterations = 0; result.iterations < options.max_iterations; ++result.iterations) {
    chain.calc_position_and_jacobian(result.q, position, jacobian);
    const Eigen::Vector3d error = target - position;
    result.error = error.norm();
    // Damped least squares: J⁺ = Jᵀ (J Jᵀ + λ² I)⁻¹ stays bounded near singular postures.
    gram_factor.compute(jacobian, lambda_squared);
    to_rest = rest_posture - result.q;
    const Eigen::Vector3d task_rest = gram_factor.solve(Eigen::Vector3d(jacobian * to_rest));
    null_step = to_rest;
    null_step.noalias() -= jacobian.transpose() * task_rest;
    null_step *= options.null_space_gain;
    if (result.error < options.tolerance && null_step.norm() < options.null_space_tolerance) {
      result.converged = true;
      break;
    }
    previous = result.q;
    const Eigen::Vector3d task_error = gram_factor.solve(error);
    result.q += null_step;
    result.q.noalias() += jacobian.transpose() * task_error;
    result.q = result.q.cwiseMax(lower).cwiseMin(upper);
    // At a joint limit the null-space pull can be blocked for good; stop once nothing moves.
    const double moved = (result.q - previous).norm();
    if (result.error < options.tolerance && moved < options.null_space_tolerance) {
      result.converged = true;
      break;
    }
    if (moved < options.stall_step) break;  // stalled away from the target
  }
  if (!result.converged) {
    // The null space did not settle (e.g. pulled against a limit): finish on position alone.
    const int position_only_iterations = 50;
    for (int i = 0; i < position_only_iterations; ++i) {
      chain.calc_position_and_jacobian(result.q, position, jacobian);
      const Eigen::Vector3d error = target - position;
      result.error = error.norm();
      if (result.error < options.tolerance) break;
      gram_factor.compute(jacobian, lambda_squared);
      result.q = (result.q + jacobian.transpose() * gram_factor.solve(error)).cwiseMax(lower).cwiseMin(upper);
    }
    result.error = (target - chain.calc_position(result.q)).norm();
    result.converged = result.error < options.tolerance;
  }
  return result;
}

InverseKinematicsResult solve_inverse_kinematics(const ArmDynamics& dynamics, const Eigen::Vector3d& target,
                                                 const Eigen::VectorXd& initial, const Eigen::VectorXd& rest_posture,
                                                 const InverseKinematicsOptions& options) {
  return solve_inverse_kinematics(make_end_effector_chain(dynamics), target, initial, rest_posture, options);
}

}  // namespace armfarm
