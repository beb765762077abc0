#include "engine/experiment/pass_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace armfarm {

namespace names = metric_names;

PassStatistics::PassStatistics(int joints, double start_time, StatisticsConfig window)
    : n_(joints),
      window_(std::move(window)),
      tracking_(joints),
      task_tracking_(3),
      model_accuracy_(joints),
      window_tracking_(3),
      share_(joints),
      saturated_ticks_(Eigen::VectorXd::Zero(joints)),
      untrusted_ticks_(Eigen::VectorXd::Zero(joints)),
      segments_(1, SegmentStatistics{start_time}) {}

void PassStatistics::add_tick(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& q, const Eigen::Vector3d& position_desired,
                              const Eigen::Vector3d& position, const ControlCommand& command) {
  if (window_.window.size() == 2) {
    const long point = calc_next_point();
    if (point >= window_.window[0] && point <= window_.window[1]) window_tracking_.add(position_desired, position);
  }
  tracking_.add(q_desired, q);
  task_tracking_.add(position_desired, position);
  share_.add(command.feed_forward, command.feedback);
  for (int j = 0; j < n_; ++j) saturated_ticks_[j] += command.saturated[j] ? 1.0 : 0.0;
  SegmentStatistics& segment = segments_.back();
  ++segment.ticks;
  segment.feedback_abs_sum += command.feedback.cwiseAbs().sum();
  segment.feed_forward_abs_sum += command.feed_forward.cwiseAbs().sum();
  segment.squared_error_sum += (q_desired - q).squaredNorm();
  longest_segment_ = std::max(longest_segment_, segment.ticks);
}

long PassStatistics::calc_next_point() const {
  return (window_.window_counting == WindowCounting::segment ? segments_.back().ticks : tracking_.count()) + 1;
}

void PassStatistics::add_model_accuracy(const Eigen::VectorXd& true_torque, const Eigen::VectorXd& feed_forward,
                                        const std::vector<bool>& output_trusted) {
  model_accuracy_.add(true_torque, feed_forward);
  for (int j = 0; j < n_; ++j) {
    if (static_cast<std::size_t>(j) < output_trusted.size() && !output_trusted[static_cast<std::size_t>(j)]) untrusted_ticks_[j] += 1.0;
  }
}

void PassStatistics::start_segment(double t, std::size_t receptive_fields) {
  segments_.back().receptive_fields = receptive_fields;
  segments_.push_back(SegmentStatistics{t});
}

double PassStatistics::calc_segment_feedback(const SegmentStatistics& segment) const {
  return segment.ticks ? segment.feedback_abs_sum / static_cast<double>(segment.ticks * n_) : std::nan("");
}

double PassStatistics::calc_segment_rmse(const SegmentStatistics& segment) const {
  return segment.ticks ? std::sqrt(segment.squared_error_sum / static_cast<double>(segment.ticks * n_)) : std::nan("");
}

void PassStatistics::write_metrics(MetricWriter& writer, const ErrorFloors& floors) const {
  writer.add_error_metrics(names::tracking_nmse, names::tracking_rmse, tracking_, floors.angle, "rad");
  const std::vector<NormalisedError> task = task_tracking_.calc_errors(floors.task, "m");
  const std::string* task_nmse[3] = {&names::tracking_nmse_x, &names::tracking_nmse_y, &names::tracking_nmse_z};
  const std::string* task_rmse[3] = {&names::tracking_rmse_x, &names::tracking_rmse_y, &names::tracking_rmse_z};
  for (int axis = 0; axis < 3; ++axis) {
    writer.add(*task_nmse[axis], task[axis].nmse ? *task[axis].nmse : std::nan(""), task[axis].reason);
    writer.add(*task_rmse[axis], task[axis].rmse);
  }
  writer.add(names::task_rmse, std::sqrt(task_tracking_.calc_mse().sum()));
  if (window_.window.size() == 2) write_window_metrics(writer, floors);
  writer.add_joints(names::ff_fb_ratio_avg, share_.calc_ratio_mean(), "no tick with nonzero torque");
  writer.add_joints(names::ff_fb_ratio_var, share_.calc_ratio_variance(), "no tick with nonzero torque");
  writer.add_joints(names::ff_abs_avg, share_.calc_feed_forward_abs_mean());
  writer.add_joints(names::fb_abs_avg, share_.calc_feedback_abs_mean());
  writer.add_joints(names::torque_saturation_fraction, saturated_ticks_ / static_cast<double>(std::max<long>(1, tracking_.count())));
  if (model_accuracy_.count() > 0) {
    writer.add_error_metrics(names::id_nmse, names::id_rmse, model_accuracy_, floors.torque, "N·m");
    const Eigen::VectorXd untrusted = untrusted_ticks_ / static_cast<double>(model_accuracy_.count());
    writer.add_joints(names::ff_untrusted_fraction, untrusted);
    writer.add(names::ff_untrusted_fraction, untrusted.mean(), "mean over " + std::to_string(n_) + " joints");
  }
}

void PassStatistics::write_window_metrics(MetricWriter& writer, const ErrorFloors& floors) const {
  const bool per_segment = window_.window_counting == WindowCounting::segment;
  std::string empty_reason;
  if (window_tracking_.count() == 0) {
    empty_reason = "no tick in the window of points " + std::to_string(window_.window[0]) + "-" + std::to_string(window_.window[1]) +
                   (per_segment ? " (counted per loop or reach; the longest had " + std::to_string(longest_segment_)
                                : " (counted over the pass; it had " + std::to_string(tracking_.count())) +
                   " points)";
  }
  const std::vector<NormalisedError> errors = window_tracking_.calc_errors(floors.task, "m");
  const std::string* nmse[3] = {&names::window_tracking_nmse_x, &names::window_tracking_nmse_y, &names::window_tracking_nmse_z};
  const std::string* rmse[3] = {&names::window_tracking_rmse_x, &names::window_tracking_rmse_y, &names::window_tracking_rmse_z};
  for (int axis = 0; axis < 3; ++axis) {
    const NormalisedError& error = errors[static_cast<std::size_t>(axis)];
    const std::string reason = empty_reason.empty() ? error.reason : empty_reason;
    writer.add(*nmse[axis], error.nmse ? *error.nmse : std::nan(""), reason);
    writer.add(*rmse[axis], error.rmse, empty_reason);  // the RMSE is defined whenever a tick fell in the window
  }
}

void PassStatistics::write_segment_metrics(MetricWriter& writer) const {
  writer.add(names::n_segments, static_cast<double>(segments_.size()));
  writer.add(names::fb_abs_avg_first_segment, calc_segment_feedback(segments_.front()));
  writer.add(names::fb_abs_avg_last_segment, calc_segment_feedback(segments_.back()));
  writer.add(names::tracking_rmse_first_segment, calc_segment_rmse(segments_.front()));
  writer.add(names::tracking_rmse_last_segment, calc_segment_rmse(segments_.back()));
}

}  // namespace armfarm
