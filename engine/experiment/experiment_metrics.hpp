#pragma once
// Every metric name an experiment job writes, in one place (to move into the metric catalog),
// and the small writer that turns per-joint vectors into Metric rows with 1-based joints.
//
// Three families, never to be confused:
//  - un-prefixed (tracking_nmse, ff_fb_ratio_avg, id_nmse, ...): the evaluation pass on the
//    *training* trajectory — for online jobs the learning pass itself, for batch jobs a control
//    run over the trajectory the model was trained on;
//  - same_run_test_nmse: batch only, the model on the collected samples withheld from training,
//    a random shuffle of 10 ms samples of the *same* runs (the thesis's 75/25 split; formerly
//    test_nmse);
//  - heldout_* (with a checkpoint): the frozen learner on a different realisation of the
//    trajectory it never trained on (heldout_evaluation.hpp).
#include "engine/experiment/job_outcome.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm::metric_names {

// Evaluation pass on the training trajectory.
inline constexpr const char* tracking_nmse = "tracking_nmse";  // per joint and mean
inline constexpr const char* tracking_nmse_x = "tracking_nmse_x";
inline constexpr const char* tracking_nmse_y = "tracking_nmse_y";
inline constexpr const char* tracking_nmse_z = "tracking_nmse_z";
inline constexpr const char* tracking_rmse = "tracking_rmse";  // rad
inline constexpr const char* task_rmse = "task_rmse";          // m
inline constexpr const char* ff_fb_ratio_avg = "ff_fb_ratio_avg";
inline constexpr const char* ff_fb_ratio_var = "ff_fb_ratio_var";
inline constexpr const char* ff_abs_avg = "ff_abs_avg";  // N·m
inline constexpr const char* fb_abs_avg = "fb_abs_avg";  // N·m
inline constexpr const char* torque_saturation_fraction = "torque_saturation_fraction";
inline constexpr const char* id_nmse = "id_nmse";  // per joint and mean
inline constexpr const char* ff_untrusted_fraction = "ff_untrusted_fraction";
inline constexpr const char* n_segments = "n_segments";
inline constexpr const char* fb_abs_avg_first_segment = "fb_abs_avg_first_segment";
inline constexpr const char* fb_abs_avg_last_segment = "fb_abs_avg_last_segment";
inline constexpr const char* tracking_rmse_first_segment = "tracking_rmse_first_segment";
inline constexpr const char* tracking_rmse_last_segment = "tracking_rmse_last_segment";

// Batch training.
inline constexpr const char* same_run_test_nmse = "same_run_test_nmse";  // per joint and mean
inline constexpr const char* n_training_samples = "n_training_samples";

// The learner and the job.
inline constexpr const char* n_receptive_fields = "n_receptive_fields";
inline constexpr const char* learner_us_per_update = "learner_us_per_update";
inline constexpr const char* learner_us_per_predict = "learner_us_per_predict";
inline constexpr const char* simulated_seconds = "simulated_seconds";
inline constexpr const char* sim_seconds_per_wall_second = "sim_seconds_per_wall_second";

// Held-out evaluation (every one carries a checkpoint). The control-pass figures are the
// evaluation-pass names above with this prefix: heldout_tracking_nmse (per joint and mean),
// heldout_tracking_nmse_x/_y/_z, heldout_tracking_rmse, heldout_task_rmse,
// heldout_ff_fb_ratio_avg, heldout_ff_fb_ratio_var, heldout_ff_abs_avg, heldout_fb_abs_avg,
// heldout_torque_saturation_fraction, heldout_id_nmse (per joint and mean),
// heldout_ff_untrusted_fraction.
inline constexpr const char* heldout_prefix = "heldout_";
inline constexpr const char* heldout_test_nmse = "heldout_test_nmse";  // per joint and mean: prediction vs applied torque
inline constexpr const char* heldout_n_test_samples = "heldout_n_test_samples";
inline constexpr const char* heldout_learner_updates = "heldout_learner_updates";  // samples learnt at the checkpoint
inline constexpr const char* heldout_n_receptive_fields = "heldout_n_receptive_fields";
inline constexpr const char* heldout_diverged = "heldout_diverged";  // 1 when the held-out control pass diverged

}  // namespace armfarm::metric_names

namespace armfarm {

/// Appends metrics to a list; per-joint vectors get the job's 1-based joint numbers.
class MetricWriter {
 public:
  MetricWriter(std::vector<Metric>& metrics, std::vector<int> joint_numbers, std::string prefix = {},
               std::optional<int> checkpoint = std::nullopt);

  void add(const std::string& name, double value);
  void add_joints(const std::string& name, const Eigen::VectorXd& values);
  /// Per joint plus the mean of the finite entries under the same name without a joint.
  void add_joints_and_mean(const std::string& name, const Eigen::VectorXd& values);

 private:
  std::vector<Metric>& metrics_;
  std::vector<int> joint_numbers_;
  std::string prefix_;
  std::optional<int> checkpoint_;
};

/// Mean of the finite entries; NaN when there are none.
double calc_mean_of_finite(const Eigen::VectorXd& values);

}  // namespace armfarm
