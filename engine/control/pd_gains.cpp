#include "engine/control/pd_gains.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {

Eigen::VectorXd expand_per_joint(const Eigen::VectorXd& values, int size, double fallback, const char* field) {
  if (values.size() == 0) return Eigen::VectorXd::Constant(size, fallback);
  if (values.size() == 1) return Eigen::VectorXd::Constant(size, values[0]);
  if (values.size() != size) {
    throw std::invalid_argument(std::string(field) + ": has " + std::to_string(values.size()) +
                                " values, expected 1 or one per active joint (" + std::to_string(size) + ")");
  }
  return values;
}

double calc_kd_scale(double gain_scale, bool keep_damping_ratio) {
  return keep_damping_ratio ? std::sqrt(gain_scale) : gain_scale;
}

PdGains make_pd_gains(const ControlConfig& control, ArmDynamics& dynamics) {
  const int n = dynamics.dof();
  const Eigen::VectorXd inertia = dynamics.calc_mass_matrix(dynamics.start_positions()).diagonal();
  PdGains gains;
  const double omega = control.bandwidth;
  gains.kp = control.kp.size() == 0 ? Eigen::VectorXd(inertia * omega * omega)
                                    : expand_per_joint(control.kp, n, 0.0, "control.kp");
  gains.kd = control.kd.size() == 0 ? Eigen::VectorXd(inertia * 2.0 * control.damping_ratio * omega)
                                    : expand_per_joint(control.kd, n, 0.0, "control.kd");
  for (int j = 0; j < n; ++j) {
    if (!(gains.kp[j] >= 0.0)) throw std::invalid_argument("control.kp[" + std::to_string(j) + "]: must not be negative");
    if (!(gains.kd[j] >= 0.0)) throw std::invalid_argument("control.kd[" + std::to_string(j) + "]: must not be negative");
  }
  return gains;
}

}  // namespace armfarm
