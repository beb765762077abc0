#pragma once
// What one experiment job returns: a value the runner hands to the results store.
//
// Naming, shared with results/ and analysis/ (the database keeps these names):
//  - `joint` is the 1-based number of a movable joint along the arm ("Joint 1" of the
//    thesis's tables), the same whatever subset of joints is active; job-level metrics have
//    no joint.
//  - metric names are snake_case and say what they measure: tracking_nmse, same_run_test_nmse,
//    ff_fb_ratio_avg, ff_fb_ratio_var, ff_abs_avg, fb_abs_avg, heldout_* ... (declared in
//    engine/experiment/experiment_metrics.hpp; sweeps/README.md lists them).
//  - series names are the thesis's recorded signals (POS, PHI, VEL, ACC, POS_D, PHI_D,
//    VEL_D, ACC_D, TOR, F, FF) plus our own (e.g. RF, the receptive fields over time).
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

enum class JobStatus { done, failed, diverged, timeout };

/// "done", "failed", "diverged", "timeout".
const char* to_string(JobStatus status);

struct Metric {
  std::string name;
  std::optional<int> joint;  ///< 1-based joint number; empty for job-level metrics
  double value = 0.0;
  /// Held-out metrics: the learning progress at which they were measured (online: completed
  /// segments of the learning pass; batch: training epochs); empty for every other metric.
  std::optional<int> checkpoint = std::nullopt;
};

/// A recorded signal: one row per sample, named columns (the first is usually time, s).
struct Series {
  std::string name;
  std::vector<std::string> columns;
  Eigen::MatrixXd rows;  ///< n_samples × columns.size()
};

struct JobOutcome {
  JobStatus status = JobStatus::done;
  std::string message;          ///< why it failed or diverged; empty when done
  double end_time = 0.0;        ///< simulated time reached, s (the divergence time when diverged)
  std::vector<Metric> metrics;
  std::vector<Series> series;
};

}  // namespace armfarm
