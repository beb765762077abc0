#pragma once
// Decides, tick by tick, whether a pass has diverged (figure 4.4 of the thesis: gains too high
// tear the arm apart): a NaN/Inf state, a joint faster than velocity_limit_factor × its limit,
// or a tracking error above max_tracking_error for longer than max_error_duration.
#include "engine/experiment/job_config.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

class DivergenceMonitor {
 public:
  /// `velocity_limits`: the model's (n, rad/s); `joint_numbers`: 1-based, for messages.
  DivergenceMonitor(const DivergenceConfig& config, const Eigen::VectorXd& velocity_limits, std::vector<int> joint_numbers);

  /// The reason the pass diverged at time t (s) with measured (q, q̇) against q_desired, or
  /// nothing. Keeps the time the error bound was first exceeded between calls.
  std::optional<std::string> check(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& q_desired);

 private:
  DivergenceConfig config_;
  Eigen::VectorXd velocity_limits_;  ///< already × velocity_limit_factor
  std::vector<int> joint_numbers_;
  double over_bound_since_ = -1.0;
};

}  // namespace armfarm
