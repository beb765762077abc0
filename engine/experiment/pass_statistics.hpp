#pragma once
// What a control pass measures, tick by tick: joint and task tracking, the feed-forward share,
// torque saturation, the feed-forward's accuracy against the true plant, and per-segment
// figures (one loop or reach: figure 6.7's TRIAL series), and task tracking over a window of
// trajectory points (statistics.window: the thesis's table 6.3). Written as metrics under a
// prefix ("" for the evaluation pass, "heldout_" for a held-out pass).
#include "engine/control/composite_controller.hpp"
#include "engine/experiment/experiment_metrics.hpp"
#include "engine/experiment/signal_statistics.hpp"
#include "engine/experiment/statistics_config.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace armfarm {

/// Statistics of one loop or reach of a pass.
struct SegmentStatistics {
  double start_time = 0.0;
  long ticks = 0;
  double feedback_abs_sum = 0.0;      ///< N·m, summed over joints and ticks
  double feed_forward_abs_sum = 0.0;  ///< N·m
  double squared_error_sum = 0.0;     ///< rad², summed over joints and ticks
  std::size_t receptive_fields = 0;   ///< the learner's size at the segment's end
};

/// Where each normalised error is defined (kNmseStdFloorFraction of the target's range).
struct ErrorFloors {
  Eigen::VectorXd angle;   ///< rad, per joint
  Eigen::VectorXd torque;  ///< N·m, per joint
  Eigen::Vector3d task;    ///< m, per axis
};

class PassStatistics {
 public:
  /// `window`: which trajectory points (one per add_tick) the window_tracking_* metrics cover.
  PassStatistics(int joints, double start_time, StatisticsConfig window = {});

  void add_tick(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& q, const Eigen::Vector3d& position_desired,
                const Eigen::Vector3d& position, const ControlCommand& command);
  /// The learner's feed-forward (zero on untrusted outputs) against the true plant's torque.
  void add_model_accuracy(const Eigen::VectorXd& true_torque, const Eigen::VectorXd& feed_forward,
                          const std::vector<bool>& output_trusted);
  /// Closes the current segment (with the learner's size then) and opens one at time t.
  void start_segment(double t, std::size_t receptive_fields);
  void end(std::size_t receptive_fields) { segments_.back().receptive_fields = receptive_fields; }

  long ticks() const { return tracking_.count(); }
  /// Ticks inside statistics.window (0 without a window).
  long window_ticks() const { return window_tracking_.count(); }
  int joints() const { return n_; }
  const std::vector<SegmentStatistics>& segments() const { return segments_; }

  /// tracking_nmse/_rmse (per joint, job), tracking_nmse/_rmse_x/_y/_z, task_rmse,
  /// ff_fb_ratio_avg/_var, ff_abs_avg, fb_abs_avg, torque_saturation_fraction and, when the
  /// learner fed forward, id_nmse/_rmse and ff_untrusted_fraction (per joint, job); with a
  /// window, window_tracking_nmse/_rmse_x/_y/_z (undefined with a reason when no tick fell in it).
  void write_metrics(MetricWriter& writer, const ErrorFloors& floors) const;
  /// n_segments and the first and last segment's fb_abs_avg and tracking_rmse.
  void write_segment_metrics(MetricWriter& writer) const;
  /// Mean |fb| (N·m) and RMS joint error (rad) of one segment; NaN when it has no ticks.
  double calc_segment_feedback(const SegmentStatistics& segment) const;
  double calc_segment_rmse(const SegmentStatistics& segment) const;

 private:
  void write_window_metrics(MetricWriter& writer, const ErrorFloors& floors) const;
  /// The 1-based number of the point add_tick is about to add, as statistics.window counts.
  long calc_next_point() const;

  int n_;
  StatisticsConfig window_;
  NmseAccumulator tracking_, task_tracking_, model_accuracy_;
  NmseAccumulator window_tracking_;  ///< task x, y, z over the window's points
  FeedForwardShareAccumulator share_;
  Eigen::VectorXd saturated_ticks_;
  Eigen::VectorXd untrusted_ticks_;  ///< per joint, ticks whose output was not trusted
  std::vector<SegmentStatistics> segments_;
  long longest_segment_ = 0;  ///< ticks of the longest segment so far (for the empty window's reason)
};

}  // namespace armfarm
