#include "engine/control/pd_gains.hpp"

#include <algorithm>
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

PdGains make_appendix_d_gains(const std::vector<int>& joint_numbers) {
  // The paramfile's lines "PID joint P I D" (thesis appendix D), joints 0-5.
  constexpr double kP[] = {60.0, 70.0, 50.0, 60.0, 60.0, 10.0};
  constexpr double kD[] = {40.0, 80.0, 30.0, 50.0, 75.0, 10.0};
  constexpr int kLines = 6;
  PdGains gains{Eigen::VectorXd(joint_numbers.size()), Eigen::VectorXd(joint_numbers.size())};
  for (std::size_t i = 0; i < joint_numbers.size(); ++i) {
    if (joint_numbers[i] < 1) throw std::invalid_argument("joint number " + std::to_string(joint_numbers[i]) + " is not 1-based");
    const int line = std::min(joint_numbers[i], kLines) - 1;
    gains.kp[static_cast<Eigen::Index>(i)] = kP[line];
    gains.kd[static_cast<Eigen::Index>(i)] = kD[line];
  }
  return gains;
}

PdGains make_pd_gains(const ControlConfig& control, ArmDynamics& dynamics, const std::vector<int>& joint_numbers) {
  return calc_pd_gains(control, dynamics.calc_mass_matrix(dynamics.start_positions()).diagonal(), joint_numbers);
}

PdGains calc_pd_gains(const ControlConfig& control, const Eigen::VectorXd& inertia, const std::vector<int>& joint_numbers) {
  const int n = static_cast<int>(inertia.size());
  PdGains placed;
  if (control.gain_set == GainSet::appendix_d) {
    placed = make_appendix_d_gains(joint_numbers);
  } else {
    const double omega = control.bandwidth;
    placed = {inertia * omega * omega, inertia * 2.0 * control.damping_ratio * omega};
  }
  if (placed.kp.size() != n) throw std::invalid_argument("control.gain_set: " + std::to_string(placed.kp.size()) +
                                                         " joint numbers for " + std::to_string(n) + " active joints");
  PdGains gains;
  gains.kp = control.kp.size() == 0 ? placed.kp : expand_per_joint(control.kp, n, 0.0, "control.kp");
  gains.kd = control.kd.size() == 0 ? placed.kd : expand_per_joint(control.kd, n, 0.0, "control.kd");
  for (int j = 0; j < n; ++j) {
    if (!(gains.kp[j] >= 0.0)) throw std::invalid_argument("control.kp[" + std::to_string(j) + "]: must not be negative");
    if (!(gains.kd[j] >= 0.0)) throw std::invalid_argument("control.kd[" + std::to_string(j) + "]: must not be negative");
  }
  return gains;
}

Eigen::MatrixXd make_gravity_stiffness(ArmDynamics& dynamics, const Eigen::VectorXd& q) {
  constexpr double kStep = 1e-6;
  const auto n = q.size();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd stiffness(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::VectorXd above = q, below = q;
    above[k] += kStep;
    below[k] -= kStep;
    stiffness.col(k) = (dynamics.calc_inverse_dynamics(above, zero, zero) - dynamics.calc_inverse_dynamics(below, zero, zero)) / (2.0 * kStep);
  }
  return stiffness;
}

Eigen::VectorXd calc_gravity_kp_floor(const std::vector<Eigen::MatrixXd>& stiffness, int n, double margin) {
  Eigen::VectorXd floor = Eigen::VectorXd::Zero(n);
  for (const Eigen::MatrixXd& h : stiffness) {
    if (h.rows() != n || h.cols() != n) throw std::invalid_argument("gravity stiffness: expected " + std::to_string(n) + " × " + std::to_string(n));
    floor = floor.cwiseMax(margin * h.cwiseAbs().rowwise().sum());
  }
  return floor;
}

Eigen::VectorXd calc_placement_inertia(const Eigen::VectorXd& start_inertia, const Eigen::VectorXd& max_inertia) {
  Eigen::VectorXd inertia = start_inertia;
  for (Eigen::Index j = 0; j < inertia.size() && j < max_inertia.size(); ++j) {
    const double floor = max_inertia[j] / kPlacementInertiaRatio;
    if (floor > inertia[j]) inertia[j] = floor;
  }
  return inertia;
}

bool has_placed_gains(const ControlConfig& control) {
  return control.gain_set == GainSet::mass_bandwidth && control.kp.size() == 0 && control.kd.size() == 0;
}

PdGains calc_floored_gains(const PdGains& gains, const Eigen::VectorXd& kp_floor, double scale) {
  if (kp_floor.size() == 0 || !(scale > 0.0)) return gains;
  PdGains floored = gains;
  for (Eigen::Index j = 0; j < gains.kp.size() && j < kp_floor.size(); ++j) {
    if (!(scale * gains.kp[j] < kp_floor[j])) continue;
    const double kp = kp_floor[j] / scale;
    if (gains.kp[j] > 0.0) floored.kd[j] = gains.kd[j] * std::sqrt(kp / gains.kp[j]);
    floored.kp[j] = kp;
  }
  return floored;
}

}  // namespace armfarm
