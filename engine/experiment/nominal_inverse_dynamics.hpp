#pragma once
// The nominal model's full inverse dynamics: rigid body plus the joints' viscous damping and
// Coulomb friction, exactly the passive forces ArmSimulation integrates (without joint-limit
// springs, which act only outside the limits). What control.feed_forward "analytic" applies.
#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Core>

namespace armfarm {

/// τ (N·m, n × 1) = ID_rigid(q, q̇, q̈) + b ∘ q̇ + F_c ∘ tanh(q̇ / `coulomb_velocity_scale`), with
/// b, F_c = `viscous`, `coulomb` (n × 1; the model's own by default overload below).
Eigen::VectorXd calc_inverse_dynamics_with_friction(ArmDynamics& dynamics, const Eigen::VectorXd& q,
                                                    const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                                    const Eigen::VectorXd& viscous, const Eigen::VectorXd& coulomb,
                                                    double coulomb_velocity_scale);

/// The same with the model's own damping and friction.
Eigen::VectorXd calc_nominal_inverse_dynamics(ArmDynamics& dynamics, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& qdd, double coulomb_velocity_scale);

}  // namespace armfarm
