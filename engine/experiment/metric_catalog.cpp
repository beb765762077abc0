#include "engine/experiment/metric_catalog.hpp"

#include <stdexcept>

namespace armfarm {

const char* to_string(MetricDirection direction) {
  switch (direction) {
    case MetricDirection::lower: return "lower";
    case MetricDirection::higher: return "higher";
    case MetricDirection::none: return "none";
  }
  return "none";
}

const char* to_string(MetricScope scope) {
  switch (scope) {
    case MetricScope::job: return "job";
    case MetricScope::joint: return "joint";
    case MetricScope::task_axis: return "task_axis";
    case MetricScope::segment: return "segment";
    case MetricScope::checkpoint: return "checkpoint";
  }
  return "job";
}

const char* to_string(MetricKind kind) {
  switch (kind) {
    case MetricKind::result: return "result";
    case MetricKind::timing: return "timing";
    case MetricKind::diagnostic: return "diagnostic";
  }
  return "result";
}

const std::vector<MetricInfo>& metric_catalog() {
  namespace n = metric_names;
  using D = MetricDirection;
  using S = MetricScope;
  using K = MetricKind;
  static const std::vector<MetricInfo> catalog = {
      {n::tracking_nmse, "1",
       "joint angle error: mean (q_d - q)^2 over var(q_d); NULL where q_d's std < 0.1 % of the joint's range",
       D::lower, S::joint, K::result},
      {n::tracking_rmse, "rad", "root mean squared joint angle error (job row: over all joints' ticks)", D::lower,
       S::joint, K::result},
      {n::tracking_nmse_x, "1", "end-effector x error: MSE over var(x_d); NULL where x_d's std < 0.1 % of 2 x reach",
       D::lower, S::task_axis, K::result},
      {n::tracking_nmse_y, "1", "end-effector y error: MSE over var(y_d); NULL where y_d's std < 0.1 % of 2 x reach",
       D::lower, S::task_axis, K::result},
      {n::tracking_nmse_z, "1", "end-effector z error: MSE over var(z_d); NULL where z_d's std < 0.1 % of 2 x reach",
       D::lower, S::task_axis, K::result},
      {n::tracking_rmse_x, "m", "root mean squared end-effector x error", D::lower, S::task_axis, K::result},
      {n::tracking_rmse_y, "m", "root mean squared end-effector y error", D::lower, S::task_axis, K::result},
      {n::tracking_rmse_z, "m", "root mean squared end-effector z error", D::lower, S::task_axis, K::result},
      {n::task_rmse, "m", "root mean squared end-effector distance from the desired point", D::lower, S::job,
       K::result},
      {n::ff_fb_ratio_avg, "1", "mean of |ff|/(|ff|+|fb|), the feed-forward share of the torque (thesis tables 6.1-6.7)",
       D::higher, S::joint, K::result},
      {n::ff_fb_ratio_var, "1", "variance of |ff|/(|ff|+|fb|) over the ticks", D::lower, S::joint, K::result},
      {n::ff_abs_avg, "N·m", "mean absolute feed-forward torque", D::none, S::joint, K::result},
      {n::fb_abs_avg, "N·m", "mean absolute feedback torque", D::lower, S::joint, K::result},
      {n::torque_saturation_fraction, "1", "fraction of ticks whose commanded torque hit the effort limit", D::lower,
       S::joint, K::result},
      {n::test_nmse, "1",
       "batch learner on held-out collected samples: torque MSE over var(torque); NULL where the torque's std < 0.1 % "
       "of 2 x effort limit",
       D::lower, S::joint, K::result},
      {n::test_rmse, "N·m", "batch learner on held-out collected samples: root mean squared torque error", D::lower,
       S::joint, K::result},
      {n::n_training_samples, "count", "samples the batch learner was trained on", D::none, S::job, K::result},
      {n::id_nmse, "1",
       "feed-forward used against the true plant's inverse dynamics at the desired state: MSE over var(true torque); "
       "NULL where its std < 0.1 % of 2 x effort limit",
       D::lower, S::joint, K::result},
      {n::id_rmse, "N·m", "root mean squared error of the feed-forward used against the true inverse dynamics",
       D::lower, S::joint, K::result},
      {n::ff_untrusted_fraction, "1",
       "fraction of ticks where the learner had no trustworthy local model for this joint's torque (its feed-forward "
       "was 0)",
       D::lower, S::joint, K::result},
      {n::n_receptive_fields, "count", "receptive fields of the learner at the end (summed over outputs)", D::none,
       S::job, K::result},
      {n::learner_us_per_update, "µs", "wall-clock time per learner update", D::lower, S::job, K::timing},
      {n::learner_us_per_predict, "µs", "wall-clock time per learner prediction", D::lower, S::job, K::timing},
      {n::n_segments, "count", "loops or reaches of the evaluation pass", D::none, S::job, K::result},
      {n::fb_abs_avg_first_segment, "N·m", "mean absolute feedback torque over the first loop or reach", D::lower,
       S::segment, K::result},
      {n::fb_abs_avg_last_segment, "N·m", "mean absolute feedback torque over the last loop or reach", D::lower,
       S::segment, K::result},
      {n::tracking_rmse_first_segment, "rad", "root mean squared joint error over the first loop or reach", D::lower,
       S::segment, K::result},
      {n::tracking_rmse_last_segment, "rad", "root mean squared joint error over the last loop or reach", D::lower,
       S::segment, K::result},
      {n::simulated_seconds, "s", "simulated time over all passes", D::none, S::job, K::result},
      {n::sim_seconds_per_wall_second, "s/s", "simulated seconds per wall-clock second", D::higher, S::job, K::timing},
      {n::work_checksum, "1", "fake job (runner tests): checksum of its busy-work loop", D::none, S::job,
       K::diagnostic},
  };
  return catalog;
}

const MetricInfo& find_metric_info(const std::string& name) {
  for (const MetricInfo& info : metric_catalog()) {
    if (info.name == name) return info;
  }
  throw std::out_of_range("no metric named '" + name + "' in the catalog");
}

}  // namespace armfarm
