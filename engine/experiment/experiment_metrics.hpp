#pragma once
// Writing a job's metrics: names come from engine/experiment/metric_catalog.hpp (each declared
// once); this writer turns per-joint vectors into Metric rows with 1-based joints, an optional
// checkpoint, and undefined values (NULL with a reason) where a figure is not finite.
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
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/signal_statistics.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

class MetricWriter {
 public:
  MetricWriter(std::vector<Metric>& metrics, std::vector<int> joint_numbers, std::string prefix = {},
               std::optional<int> checkpoint = std::nullopt);

  /// A job-level value; a non-finite one is stored undefined with `reason` (or a generic one).
  void add(const std::string& name, double value, std::string reason = {});
  /// One row per joint; non-finite entries undefined with `reason_if_undefined`.
  void add_joints(const std::string& name, const Eigen::VectorXd& values, const std::string& reason_if_undefined = {});
  /// Per joint nMSE (undefined below `std_floor`) and RMSE, then the job rows: the nMSE mean over
  /// the joints where it is defined (its reason says which), the RMSE over every joint's ticks.
  void add_error_metrics(const std::string& nmse_name, const std::string& rmse_name, const NmseAccumulator& errors,
                         const Eigen::VectorXd& std_floor, const std::string& unit);

 private:
  Metric make_metric(const std::string& name, std::optional<int> joint, double value, std::string reason) const;

  std::vector<Metric>& metrics_;
  std::vector<int> joint_numbers_;
  std::string prefix_;
  std::optional<int> checkpoint_;
};

}  // namespace armfarm
