#include "engine/control/composite_controller.hpp"

#include <utility>

namespace armfarm {

CompositeController::CompositeController(ControlMode mode, PdGains gains, double gain_scale, Eigen::VectorXd effort_limits,
                                         bool limit_torque)
    : CompositeController(mode, std::move(gains), gain_scale, gain_scale, std::move(effort_limits), limit_torque) {}

CompositeController::CompositeController(ControlMode mode, PdGains gains, double kp_scale, double kd_scale,
                                         Eigen::VectorXd effort_limits, bool limit_torque)
    : mode_(mode),
      kp_(gains.kp * kp_scale),
      kd_(gains.kd * kd_scale),
      effort_limits_(std::move(effort_limits)),
      limit_torque_(limit_torque) {}

ControlCommand CompositeController::calc_command(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& qd_desired,
                                                 const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                 const Eigen::VectorXd& feed_forward) const {
  const int n = static_cast<int>(q.size());
  ControlCommand command;
  command.feedback = Eigen::VectorXd::Zero(n);
  command.feed_forward = Eigen::VectorXd::Zero(n);
  if (mode_ != ControlMode::open_loop) {
    command.feedback = kp_.cwiseProduct(q_desired - q) + kd_.cwiseProduct(qd_desired - qd);
  }
  if (mode_ != ControlMode::feedback) command.feed_forward = feed_forward;
  command.torque = command.feedback + command.feed_forward;
  command.saturated = Eigen::Matrix<bool, Eigen::Dynamic, 1>::Constant(n, false);
  if (limit_torque_) {
    for (int j = 0; j < n; ++j) {
      const double limit = effort_limits_[j];
      if (command.torque[j] > limit || command.torque[j] < -limit) {
        command.saturated[j] = true;
        command.torque[j] = command.torque[j] > 0.0 ? limit : -limit;
      }
    }
  }
  return command;
}

}  // namespace armfarm
