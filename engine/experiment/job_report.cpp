#include "engine/experiment/job_report.hpp"

#include <algorithm>
#include <cmath>

namespace armfarm {

namespace names = metric_names;

void write_evaluation_report(MetricWriter& writer, const PassStatistics& statistics, const ErrorFloors& floors,
                             SeriesRecorder& recorder) {
  statistics.write_metrics(writer, floors);
  statistics.write_segment_metrics(writer);
  const std::vector<SegmentStatistics>& segments = statistics.segments();
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const SegmentStatistics& segment = segments[s];
    const double ticks = static_cast<double>(std::max<long>(1, segment.ticks));
    Eigen::VectorXd row(6);
    row << static_cast<double>(s + 1), segment.start_time, statistics.calc_segment_feedback(segment),
        segment.feed_forward_abs_sum / ticks / statistics.joints(), statistics.calc_segment_rmse(segment),
        static_cast<double>(segment.receptive_fields);
    recorder.add_row("TRIAL", {"segment", "t", "fb_abs_avg", "ff_abs_avg", "tracking_rmse", "n_receptive_fields"}, row);
  }
}

void write_batch_training_report(MetricWriter& writer, const BatchTrainingResult& training, const ErrorFloors& floors) {
  if (training.same_run_test.count() > 0) {
    writer.add_error_metrics(names::same_run_test_nmse, names::same_run_test_rmse, training.same_run_test, floors.torque, "N·m");
  }
  if (training.training_samples > 0) writer.add(names::n_training_samples, static_cast<double>(training.training_samples));
}

double calc_fields_per_output(const Learner& learner) {
  return static_cast<double>(learner.size()) / std::max(1, learner.output_dim());
}

void write_learner_report(MetricWriter& writer, const Learner& learner, const LearnerClock& clock) {
  writer.add(names::n_receptive_fields, static_cast<double>(learner.size()));
  writer.add(names::n_receptive_fields_per_output, calc_fields_per_output(learner));
  // The one-off fit runs inside one update(): reported apart, not spread over the updates.
  const double fit_seconds = learner.fit_seconds();
  writer.add(names::learner_us_per_update,
             clock.updates ? 1e6 * std::max(0.0, clock.update_seconds - fit_seconds) / static_cast<double>(clock.updates) : std::nan(""));
  writer.add(names::learner_us_per_predict,
             clock.predictions ? 1e6 * clock.predict_seconds / static_cast<double>(clock.predictions) : std::nan(""));
  writer.add(names::learner_memory_bytes, static_cast<double>(learner.calc_memory_bytes()));
  writer.add(names::learner_fit_seconds, fit_seconds);
}

void write_tick_report(MetricWriter& writer, const TickClock& clock) {
  if (clock.ticks == 0) return;
  const double per_tick = 1e6 / static_cast<double>(clock.ticks);
  writer.add(names::tick_us_total, clock.total() * per_tick);
  writer.add(names::tick_us_physics, clock.physics * per_tick);
  writer.add(names::tick_us_feed_forward, clock.feed_forward * per_tick);
  writer.add(names::tick_us_control, clock.control * per_tick);
  writer.add(names::tick_us_true_dynamics, clock.true_dynamics * per_tick);
  writer.add(names::tick_us_statistics, clock.statistics * per_tick);
  writer.add(names::tick_us_learning, clock.learning * per_tick);
}

void write_cost_report(MetricWriter& writer, double simulated_seconds, double wall_seconds) {
  writer.add(names::simulated_seconds, simulated_seconds);
  writer.add(names::sim_seconds_per_wall_second, wall_seconds > 0.0 ? simulated_seconds / wall_seconds : std::nan(""));
}

}  // namespace armfarm
