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

/// The recorded time of a tick at simulated time `t` (s): the tick's number i = round(t / dt)
/// times dt, computed as i / (1/dt) when 1/dt is a whole number (so dt = 0.01 records 0.1, 0.2,
/// 0.3 as the doubles nearest those decimals, which print shortest as "0.1", "0.2", "0.3"),
/// as i·dt otherwise. The plant's own clock accumulates dt and reads 0.09999999999999999.
double calc_recorded_tick_time(double t, double dt);

}  // namespace armfarm
