#include "engine/experiment/tick_recording.hpp"

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

}  // namespace armfarm
