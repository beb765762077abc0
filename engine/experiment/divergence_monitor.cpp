#include "engine/experiment/divergence_monitor.hpp"

#include <cmath>
#include <utility>

namespace armfarm {

DivergenceMonitor::DivergenceMonitor(const DivergenceConfig& config, const Eigen::VectorXd& velocity_limits,
                                     std::vector<int> joint_numbers)
    : config_(config), velocity_limits_(velocity_limits * config.velocity_limit_factor), joint_numbers_(std::move(joint_numbers)) {}

std::optional<std::string> DivergenceMonitor::check(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                    const Eigen::VectorXd& q_desired) {
  if (!q.allFinite() || !qd.allFinite()) return std::string("the state became NaN or Inf");
  for (Eigen::Index j = 0; j < qd.size(); ++j) {
    if (std::fabs(qd[j]) > velocity_limits_[j]) {
      return "joint " + std::to_string(joint_numbers_[static_cast<std::size_t>(j)]) + " velocity " + std::to_string(qd[j]) +
             " rad/s exceeds its limit " + std::to_string(velocity_limits_[j]) + " rad/s";
    }
  }
  if ((q_desired - q).cwiseAbs().maxCoeff() > config_.max_tracking_error) {
    if (over_bound_since_ < 0.0) over_bound_since_ = t;
    if (t - over_bound_since_ > config_.max_error_duration) {
      return "tracking error above " + std::to_string(config_.max_tracking_error) + " rad for more than " +
             std::to_string(config_.max_error_duration) + " s";
    }
  } else {
    over_bound_since_ = -1.0;
  }
  return std::nullopt;
}

}  // namespace armfarm
