#pragma once
// The thesis's controller (appendix A): a PD feedback term plus a feed-forward term, in one of
// three modes, with the command clipped to the joints' effort limits.
// Units: SI and radians; vectors are n_active × 1.
#include "engine/control/pd_gains.hpp"
#include "engine/control/control_config.hpp"

#include <Eigen/Core>

namespace armfarm {

struct ControlCommand {
  Eigen::VectorXd feed_forward;  ///< N·m, the term actually applied (0 in feedback mode)
  Eigen::VectorXd feedback;      ///< N·m, the PD term actually applied (0 in open-loop mode)
  Eigen::VectorXd torque;        ///< N·m, what the plant receives (clipped)
  Eigen::Matrix<bool, Eigen::Dynamic, 1> saturated;  ///< per joint: the command was clipped
};

/// Immutable description of the controller of one job.
class CompositeController {
 public:
  /// `gains` at full scale; `gain_scale` multiplies them; `effort_limits` (N·m, +inf for none)
  /// apply when `limit_torque`.
  CompositeController(ControlMode mode, PdGains gains, double gain_scale, Eigen::VectorXd effort_limits, bool limit_torque);
  /// The same with kp × kp_scale and kd × kd_scale (see calc_kd_scale()).
  CompositeController(ControlMode mode, PdGains gains, double kp_scale, double kd_scale, Eigen::VectorXd effort_limits,
                      bool limit_torque);

  /// The command for desired (q_d, q̇_d), measured (q, q̇) and a feed-forward torque.
  ControlCommand calc_command(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& qd_desired, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& qd, const Eigen::VectorXd& feed_forward) const;

  const Eigen::VectorXd& kp() const { return kp_; }  ///< scaled
  const Eigen::VectorXd& kd() const { return kd_; }  ///< scaled

 private:
  ControlMode mode_;
  Eigen::VectorXd kp_, kd_, effort_limits_;
  bool limit_torque_;
};

}  // namespace armfarm
