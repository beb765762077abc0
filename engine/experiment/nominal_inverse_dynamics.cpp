#include "engine/experiment/nominal_inverse_dynamics.hpp"

#include <cmath>

namespace armfarm {

Eigen::VectorXd calc_inverse_dynamics_with_friction(ArmDynamics& dynamics, const Eigen::VectorXd& q,
                                                    const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                                    const Eigen::VectorXd& viscous, const Eigen::VectorXd& coulomb,
                                                    double coulomb_velocity_scale) {
  Eigen::VectorXd torque = dynamics.calc_inverse_dynamics(q, qd, qdd);
  for (int j = 0; j < torque.size(); ++j) {
    torque[j] += viscous[j] * qd[j] + coulomb[j] * std::tanh(qd[j] / coulomb_velocity_scale);
  }
  return torque;
}

Eigen::VectorXd calc_nominal_inverse_dynamics(ArmDynamics& dynamics, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& qdd, double coulomb_velocity_scale) {
  return calc_inverse_dynamics_with_friction(dynamics, q, qd, qdd, dynamics.viscous_damping(),
                                             dynamics.coulomb_friction(), coulomb_velocity_scale);
}

}  // namespace armfarm
