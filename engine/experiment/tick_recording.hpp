#pragma once
// Recording: one control tick's signals into the series a job asked for (the thesis's POS,
// POS_D, PHI, PHI_D, VEL, VEL_D, ACC, ACC_D, TOR, F, FF and our RF).
#include "engine/control/composite_controller.hpp"
#include "engine/experiment/series_recorder.hpp"

#include <Eigen/Core>

#include <cstddef>

namespace armfarm {

struct TickRecord {
  double t;                              ///< s
  const Eigen::VectorXd& q;              ///< measured, rad
  const Eigen::VectorXd& qd;             ///< rad/s
  const Eigen::VectorXd& qdd;            ///< the last measured acceleration, rad/s²
  const Eigen::VectorXd& q_desired;
  const Eigen::VectorXd& qd_desired;
  const Eigen::VectorXd& qdd_desired;
  const Eigen::Vector3d& position;       ///< end effector, m, world frame
  const Eigen::Vector3d& position_desired;
  const ControlCommand& command;
  std::size_t receptive_fields;          ///< the learner's size (0 without one)
};

void record_tick(SeriesRecorder& recorder, const TickRecord& tick);

}  // namespace armfarm
