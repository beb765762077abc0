#pragma once
// Every metric a job can record, declared once: its name, unit, meaning, which way is better,
// what it is measured over (scope) and whether it is a result or a machine-dependent
// timing/diagnostic. The job code takes names from here (metric_names::…); the runner copies
// the catalog into each database's `metric_info` table, from which tables, comparisons, merges,
// plots and reports read directions, units and kinds. Adding a metric is one entry in
// metric_catalog.cpp (and, if code writes it, one constant below).
#include <string>
#include <vector>

namespace armfarm {

enum class MetricDirection { lower, higher, none };
/// job: one value per job; joint: one per joint (1-based) plus, unless the meaning says
/// otherwise, a job-level row holding the mean over the joints with a defined value;
/// task_axis: one end-effector axis; segment: one loop or reach of the trajectory;
/// checkpoint: one row per (joint,) checkpoint of a held-out evaluation.
enum class MetricScope { job, joint, task_axis, segment, checkpoint };
/// result: the same for the same configuration and seed (compared by merge and compare);
/// timing: depends on the machine and its load; diagnostic: bookkeeping that may vary run to run.
enum class MetricKind { result, timing, diagnostic };

struct MetricInfo {
  std::string name;
  std::string unit;     ///< SI symbol, "1" for dimensionless, "count" for counts
  std::string meaning;  ///< one line
  MetricDirection direction = MetricDirection::none;
  MetricScope scope = MetricScope::job;
  MetricKind kind = MetricKind::result;
};

/// "lower", "higher", "none"; "job", "joint", "task_axis", "segment", "checkpoint";
/// "result", "timing", "diagnostic" (the spellings stored in metric_info).
const char* to_string(MetricDirection direction);
const char* to_string(MetricScope scope);
const char* to_string(MetricKind kind);

/// The catalog, in a stable order.
const std::vector<MetricInfo>& metric_catalog();
/// The evaluation-pass metrics a held-out control pass also writes, as heldout_<name>.
const std::vector<std::string>& heldout_control_metric_names();
/// The entry of `name`; throws std::out_of_range for a name not in the catalog.
const MetricInfo& find_metric_info(const std::string& name);

/// Where a normalised error (nMSE) is defined: the target's standard deviation must reach this
/// fraction of the target's range (a joint's position range, a joint's torque range
/// 2·effort limit, the end effector's 2·reach). Below it the target barely moves and the
/// ratio divides by numerical noise; the nMSE is stored as NULL with the reason, the RMSE
/// beside it stays meaningful. sweeps/README.md ("Metrics") gives the reasoning.
inline constexpr double kNmseStdFloorFraction = 1e-3;

/// The names the job code writes. Each appears in metric_catalog().
namespace metric_names {
inline const std::string tracking_nmse = "tracking_nmse";
inline const std::string tracking_rmse = "tracking_rmse";
inline const std::string tracking_nmse_x = "tracking_nmse_x";
inline const std::string tracking_nmse_y = "tracking_nmse_y";
inline const std::string tracking_nmse_z = "tracking_nmse_z";
inline const std::string tracking_rmse_x = "tracking_rmse_x";
inline const std::string tracking_rmse_y = "tracking_rmse_y";
inline const std::string tracking_rmse_z = "tracking_rmse_z";
inline const std::string task_rmse = "task_rmse";
// Over statistics.window's trajectory points only (statistics_config.hpp); written when it is set.
inline const std::string window_tracking_nmse_x = "window_tracking_nmse_x";
inline const std::string window_tracking_nmse_y = "window_tracking_nmse_y";
inline const std::string window_tracking_nmse_z = "window_tracking_nmse_z";
inline const std::string window_tracking_rmse_x = "window_tracking_rmse_x";
inline const std::string window_tracking_rmse_y = "window_tracking_rmse_y";
inline const std::string window_tracking_rmse_z = "window_tracking_rmse_z";
inline const std::string ff_fb_ratio_avg = "ff_fb_ratio_avg";
inline const std::string ff_fb_ratio_var = "ff_fb_ratio_var";
inline const std::string ff_abs_avg = "ff_abs_avg";
inline const std::string fb_abs_avg = "fb_abs_avg";
inline const std::string torque_saturation_fraction = "torque_saturation_fraction";
inline const std::string same_run_test_nmse = "same_run_test_nmse";  // formerly test_nmse
inline const std::string same_run_test_rmse = "same_run_test_rmse";  // formerly test_rmse
inline const std::string n_training_samples = "n_training_samples";
inline const std::string id_nmse = "id_nmse";
inline const std::string id_rmse = "id_rmse";
inline const std::string ff_untrusted_fraction = "ff_untrusted_fraction";
inline const std::string n_receptive_fields = "n_receptive_fields";
inline const std::string n_receptive_fields_per_output = "n_receptive_fields_per_output";
inline const std::string learner_us_per_update = "learner_us_per_update";
inline const std::string learner_us_per_predict = "learner_us_per_predict";
inline const std::string learner_memory_bytes = "learner_memory_bytes";
inline const std::string learner_fit_seconds = "learner_fit_seconds";
inline const std::string n_segments = "n_segments";
inline const std::string fb_abs_avg_first_segment = "fb_abs_avg_first_segment";
inline const std::string fb_abs_avg_last_segment = "fb_abs_avg_last_segment";
inline const std::string tracking_rmse_first_segment = "tracking_rmse_first_segment";
inline const std::string tracking_rmse_last_segment = "tracking_rmse_last_segment";
inline const std::string simulated_seconds = "simulated_seconds";
inline const std::string pd_substeps_used = "pd_substeps_used";
inline const std::string integrator_steps_used = "integrator_steps_used";
inline const std::string sim_seconds_per_wall_second = "sim_seconds_per_wall_second";
// Where a tick of the evaluation pass goes (TickClock, control_pass.hpp), µs per tick.
inline const std::string tick_us_total = "tick_us_total";
inline const std::string tick_us_physics = "tick_us_physics";
inline const std::string tick_us_feed_forward = "tick_us_feed_forward";
inline const std::string tick_us_control = "tick_us_control";
inline const std::string tick_us_true_dynamics = "tick_us_true_dynamics";
inline const std::string tick_us_statistics = "tick_us_statistics";
inline const std::string tick_us_learning = "tick_us_learning";
inline const std::string work_checksum = "work_checksum";
// Held-out evaluation (engine/experiment/heldout_evaluation.hpp): every row carries a checkpoint.
// The control-pass figures are the evaluation-pass names with this prefix.
inline const std::string heldout_prefix = "heldout_";
inline const std::string heldout_test_nmse = "heldout_test_nmse";
inline const std::string heldout_test_rmse = "heldout_test_rmse";
inline const std::string heldout_n_test_samples = "heldout_n_test_samples";
inline const std::string heldout_learner_updates = "heldout_learner_updates";
inline const std::string heldout_n_receptive_fields = "heldout_n_receptive_fields";
inline const std::string heldout_n_receptive_fields_per_output = "heldout_n_receptive_fields_per_output";
inline const std::string heldout_diverged = "heldout_diverged";
}  // namespace metric_names

}  // namespace armfarm
