#include "engine/experiment/tick_recording.hpp"

#include <cmath>

namespace armfarm {

void record_tick(SeriesRecorder& recorder, const TickRecord& tick) {
  recorder.add("POS", tick.t, tick.position);
  recorder.add("POS_D", tick.t, tick.position_desired);
  recorder.add("PHI", tick.t, tick.q);
  recorder.add("PHI_D", tick.t, tick.q_desired);
  recorder.add("VEL", tick.t, tick.qd);
  recorder.add("VEL_D", tick.t, tick.qd_desired);
  recorder.add("ACC", tick.t, tick.qdd);
  recorder.add("ACC_D", tick.t, tick.qdd_desired);
  recorder.add("TOR", tick.t, tick.command.torque);
  recorder.add("F", tick.t, tick.command.feedback);
  recorder.add("FF", tick.t, tick.command.feed_forward);
  if (recorder.wants("RF")) recorder.add("RF", tick.t, Eigen::VectorXd::Constant(1, static_cast<double>(tick.receptive_fields)));
}

double calc_recorded_tick_time(double t, double dt) {
  const double tick = std::round(t / dt);
  const double ticks_per_second = std::round(1.0 / dt);
  if (ticks_per_second >= 1.0 && std::abs(ticks_per_second * dt - 1.0) < 1e-12) return tick / ticks_per_second;
  return tick * dt;
}

}  // namespace armfarm
