#include "engine/experiment/metric_catalog.hpp"

#include <iterator>
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

namespace {

// The entries' shorthand: n::name, D::direction, S::scope, K::kind.
namespace n = metric_names;
using D = MetricDirection;
using S = MetricScope;
using K = MetricKind;

/// Tracking of the evaluation pass: per joint (rad) and per end-effector axis (m), over all its ticks.
std::vector<MetricInfo> make_tracking_entries() {
  return {
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
  };
}

/// Tracking over statistics.window's trajectory points only (written when the window is set).
std::vector<MetricInfo> make_window_entries() {
  return {
      {n::window_tracking_nmse_x, "1",
       "end-effector x error over the trajectory points of statistics.window only (counted per loop or reach, or over "
       "the pass: statistics.window_counting): MSE over var(x_d) within the window; NULL where that std < 0.1 % of 2 x "
       "reach or no tick fell in the window",
       D::lower, S::task_axis, K::result},
      {n::window_tracking_nmse_y, "1",
       "end-effector y error over the trajectory points of statistics.window only (thesis table 6.3: points 325-750): "
       "MSE over var(y_d) within the window; NULL where that std < 0.1 % of 2 x reach or no tick fell in the window",
       D::lower, S::task_axis, K::result},
      {n::window_tracking_nmse_z, "1",
       "end-effector z error over the trajectory points of statistics.window only (thesis table 6.3: points 325-750): "
       "MSE over var(z_d) within the window; NULL where that std < 0.1 % of 2 x reach or no tick fell in the window",
       D::lower, S::task_axis, K::result},
      {n::window_tracking_rmse_x, "m", "root mean squared end-effector x error over statistics.window's trajectory points",
       D::lower, S::task_axis, K::result},
      {n::window_tracking_rmse_y, "m", "root mean squared end-effector y error over statistics.window's trajectory points",
       D::lower, S::task_axis, K::result},
      {n::window_tracking_rmse_z, "m", "root mean squared end-effector z error over statistics.window's trajectory points",
       D::lower, S::task_axis, K::result},
  };
}

/// How the evaluation pass's torque splits into feed-forward and feedback (N·m), and saturation.
std::vector<MetricInfo> make_torque_share_entries() {
  return {
      {n::ff_fb_ratio_avg, "1", "mean of |ff|/(|ff|+|fb|), the feed-forward share of the torque (thesis tables 6.1-6.7)",
       D::higher, S::joint, K::result},
      {n::ff_fb_ratio_var, "1", "variance of |ff|/(|ff|+|fb|) over the ticks", D::lower, S::joint, K::result},
      {n::ff_abs_avg, "N·m", "mean absolute feed-forward torque", D::none, S::joint, K::result},
      {n::fb_abs_avg, "N·m", "mean absolute feedback torque", D::lower, S::joint, K::result},
      {n::torque_saturation_fraction, "1", "fraction of ticks whose commanded torque hit the effort limit", D::lower,
       S::joint, K::result},
  };
}

/// Batch training scored on the collected samples it withheld (learning.mode batch).
std::vector<MetricInfo> make_batch_training_entries() {
  return {
      {n::same_run_test_nmse, "1",
       "batch learner on the collected samples withheld from training (a random shuffle of 10 ms samples of the same "
       "runs, not held-out data): torque MSE over var(torque); NULL where the torque's std < 0.1 % of 2 x effort limit. "
       "With learning.collect_start_spread > 0 it includes the perturbed repeats' start transients, where no field is "
       "trusted and the prediction is 0: they can dominate it and make it worse than heldout_test_nmse",
       D::lower, S::joint, K::result},
      {n::same_run_test_rmse, "N·m", "batch learner on the withheld samples of the same runs: root mean squared torque error",
       D::lower, S::joint, K::result},
      {n::n_training_samples, "count", "samples the batch learner was trained on", D::none, S::job, K::result},
  };
}

/// The feed-forward used against the true plant's inverse dynamics at the desired state.
std::vector<MetricInfo> make_model_accuracy_entries() {
  return {
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
  };
}

/// The learner at the end of the job: its size, its memory and the wall time of its calls.
std::vector<MetricInfo> make_learner_entries() {
  return {
      {n::n_receptive_fields, "count", "learner size at the end: LWPR receptive fields summed over outputs, SSGPR frequencies D", D::none,
       S::job, K::result},
      {n::n_receptive_fields_per_output, "count",
       "n_receptive_fields over the learner's outputs (LWPR: the fields of one output, every output's count when update_D "
       "is off, since the outputs then allocate at the same inputs; the count the thesis prints)",
       D::none, S::job, K::result},
      {n::learner_us_per_update, "µs", "wall-clock time per learner update (without a one-off hyperparameter fit)", D::lower, S::job, K::timing},
      {n::learner_us_per_predict, "µs", "wall-clock time per learner prediction", D::lower, S::job, K::timing},
      {n::learner_memory_bytes, "B", "numbers the learnt model stores at the end, 8 bytes per double (no allocator overhead)",
       D::lower, S::job, K::result},
      {n::learner_fit_seconds, "s", "wall-clock time of the learner's one-off hyperparameter fit (SSGPR fit_samples > 0; 0 otherwise)",
       D::lower, S::job, K::timing},
  };
}

/// Loops or reaches of the evaluation pass: the first against the last.
std::vector<MetricInfo> make_segment_entries() {
  return {
      {n::n_segments, "count", "loops or reaches of the evaluation pass", D::none, S::job, K::result},
      {n::fb_abs_avg_first_segment, "N·m", "mean absolute feedback torque over the first loop or reach", D::lower,
       S::segment, K::result},
      {n::fb_abs_avg_last_segment, "N·m", "mean absolute feedback torque over the last loop or reach", D::lower,
       S::segment, K::result},
      {n::tracking_rmse_first_segment, "rad", "root mean squared joint error over the first loop or reach", D::lower,
       S::segment, K::result},
      {n::tracking_rmse_last_segment, "rad", "root mean squared joint error over the last loop or reach", D::lower,
       S::segment, K::result},
  };
}

/// The job's cost: simulated time, the steps it ran with, and simulated against wall time.
std::vector<MetricInfo> make_cost_entries() {
  return {
      {n::simulated_seconds, "s", "simulated time over all passes", D::none, S::job, K::result},
      {n::pd_substeps_used, "count", "PD periods per control tick the job ran with (pd_substeps, \"auto\" resolved)", D::none, S::job,
       K::result},
      {n::integrator_steps_used, "count",
       "runge_kutta_4 steps per PD period the job ran with (integrator_steps_per_tick, \"auto\" resolved)", D::none, S::job, K::result},
      {n::sim_seconds_per_wall_second, "s/s", "simulated seconds per wall-clock second", D::higher, S::job, K::timing},
  };
}

/// Where an evaluation tick's wall time goes (TickClock, control_pass.hpp), µs per tick.
std::vector<MetricInfo> make_tick_entries() {
  return {
      {n::tick_us_total, "µs", "wall-clock time per tick of the evaluation pass (the sum of the tick_us_* stages)", D::lower,
       S::job, K::timing},
      {n::tick_us_physics, "µs", "per evaluation tick: stepping the plant (integrator)", D::lower, S::job, K::timing},
      {n::tick_us_feed_forward, "µs", "per evaluation tick: the feed-forward (learner prediction or nominal inverse dynamics)",
       D::lower, S::job, K::timing},
      {n::tick_us_control, "µs", "per evaluation tick: the controller's command and the divergence check", D::lower, S::job,
       K::timing},
      {n::tick_us_true_dynamics, "µs", "per evaluation tick: the true plant's inverse dynamics for id_nmse", D::lower, S::job,
       K::timing},
      {n::tick_us_statistics, "µs", "per evaluation tick: tracking statistics and series recording", D::lower, S::job,
       K::timing},
      {n::tick_us_learning, "µs", "per evaluation tick: the measured sample and the learner's update", D::lower, S::job,
       K::timing},
  };
}

/// Bookkeeping of the runner's tests.
std::vector<MetricInfo> make_diagnostic_entries() {
  return {
      {n::work_checksum, "1", "fake job (runner tests): checksum of its busy-work loop", D::none, S::job,
       K::diagnostic},
  };
}

/// Everything but the held-out evaluation, group by group in the catalog's order.
std::vector<MetricInfo> make_job_entries() {
  std::vector<MetricInfo> entries;
  for (std::vector<MetricInfo> (*make_group)() :
       {make_tracking_entries, make_window_entries, make_torque_share_entries, make_batch_training_entries,
        make_model_accuracy_entries, make_learner_entries, make_segment_entries, make_cost_entries, make_tick_entries,
        make_diagnostic_entries}) {
    std::vector<MetricInfo> group = make_group();
    entries.insert(entries.end(), std::make_move_iterator(group.begin()), std::make_move_iterator(group.end()));
  }
  return entries;
}

/// The held-out evaluation's entries (engine/experiment/heldout_evaluation.hpp): the frozen
/// learner on a held-out realisation of the trajectory, one row per (joint,) checkpoint. The
/// control-pass figures mirror the evaluation pass's entries under the heldout_ prefix.
std::vector<MetricInfo> make_heldout_entries(const std::vector<MetricInfo>& job_entries) {
  std::vector<MetricInfo> entries = {
      {n::heldout_test_nmse, "1",
       "frozen learner on the held-out samples (never trained on): torque MSE over var(torque); NULL below the floor",
       D::lower, S::checkpoint, K::result},
      {n::heldout_test_rmse, "N·m", "frozen learner on the held-out samples: root mean squared torque error", D::lower,
       S::checkpoint, K::result},
      {n::heldout_n_test_samples, "count", "held-out samples scored", D::none, S::checkpoint, K::result},
      {n::heldout_learner_updates, "count", "samples the learner had learnt at the checkpoint", D::none, S::checkpoint,
       K::result},
      {n::heldout_n_receptive_fields, "count", "learner size at the checkpoint (LWPR receptive fields, SSGPR frequencies D)", D::none,
       S::checkpoint, K::result},
      {n::heldout_n_receptive_fields_per_output, "count", "heldout_n_receptive_fields over the learner's outputs (as n_receptive_fields_per_output)",
       D::none, S::checkpoint, K::result},
      {n::heldout_diverged, "1", "1 when the held-out control pass diverged (its figures cover the ticks run)", D::lower,
       S::checkpoint, K::result},
  };
  for (const std::string& name : heldout_control_metric_names()) {
    for (const MetricInfo& info : job_entries) {
      if (info.name == name) {
        entries.push_back({n::heldout_prefix + info.name, info.unit, "held-out control pass, frozen learner: " + info.meaning,
                           info.direction, S::checkpoint, info.kind});
      }
    }
  }
  return entries;
}

std::vector<MetricInfo> make_catalog() {
  std::vector<MetricInfo> catalog = make_job_entries();
  const std::vector<MetricInfo> heldout = make_heldout_entries(catalog);
  catalog.insert(catalog.end(), heldout.begin(), heldout.end());
  return catalog;
}

}  // namespace

const std::vector<std::string>& heldout_control_metric_names() {
  namespace n = metric_names;
  static const std::vector<std::string> names = {
      n::tracking_nmse, n::tracking_rmse, n::tracking_nmse_x, n::tracking_nmse_y, n::tracking_nmse_z,
      n::tracking_rmse_x, n::tracking_rmse_y, n::tracking_rmse_z, n::task_rmse, n::window_tracking_nmse_x,
      n::window_tracking_nmse_y, n::window_tracking_nmse_z, n::window_tracking_rmse_x, n::window_tracking_rmse_y,
      n::window_tracking_rmse_z, n::ff_fb_ratio_avg,
      n::ff_fb_ratio_var, n::ff_abs_avg, n::fb_abs_avg, n::torque_saturation_fraction, n::id_nmse, n::id_rmse,
      n::ff_untrusted_fraction};
  return names;
}

const std::vector<MetricInfo>& metric_catalog() {
  static const std::vector<MetricInfo> catalog = make_catalog();
  return catalog;
}

const MetricInfo& find_metric_info(const std::string& name) {
  for (const MetricInfo& info : metric_catalog()) {
    if (info.name == name) return info;
  }
  throw std::out_of_range("no metric named '" + name + "' in the catalog");
}

}  // namespace armfarm
