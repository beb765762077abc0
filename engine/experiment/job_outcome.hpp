#pragma once
// What one experiment job returns: a value the runner hands to the results store.
//
// Naming, shared with results/ and analysis/ (the database keeps these names):
//  - `joint` is the 1-based number of a movable joint along the arm ("Joint 1" of the
//    thesis's tables), the same whatever subset of joints is active; job-level metrics have
//    no joint.
//  - metric names come from engine/experiment/metric_catalog.hpp (name, unit, meaning,
//    direction, scope, kind); sweeps/README.md lists them.
//  - series names are the thesis's recorded signals (POS, PHI, VEL, ACC, POS_D, PHI_D,
//    VEL_D, ACC_D, TOR, F, FF) plus our own (e.g. RF, the receptive fields over time).
#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

enum class JobStatus { done, failed, diverged, timeout };

/// "done", "failed", "diverged", "timeout".
const char* to_string(JobStatus status);

/// One recorded value. An undefined value (e.g. an nMSE whose target did not vary) has no
/// `value` and says why in `reason`; a defined one may carry a note there too (a mean that
/// left out joints says which).
/// A held-out evaluation checkpoint (a type of its own, so that {name, joint, value} written
/// in the old three-field form does not compile into a checkpoint).
struct MetricCheckpoint {
  std::int64_t number = 0;  ///< orders the checkpoints of a job; the catalog entry says what it counts
};

struct Metric {
  std::string name;                      ///< a metric_catalog() name
  std::optional<int> joint;              ///< 1-based joint number; empty for job-level metrics
  std::optional<MetricCheckpoint> checkpoint;  ///< held-out evaluation checkpoint; empty otherwise
  std::optional<double> value;           ///< empty = undefined (stored as NULL)
  std::string reason;                    ///< why undefined, or what a mean left out; may be empty
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
  /// With learning.store_model: the learner's model file at the end of the job
  /// (engine/learning/learner_model_file.hpp), also when the job diverged or stopped; else empty.
  std::string model_file;
};

}  // namespace armfarm
