// Batch training takes a stop (issue 23: table 6.4's 200 000-sample jobs trained for more than
// 25 minutes and a Ctrl-C waited for the end of training). The stop is counted in polls, not
// timed: each test fires should_stop at a chosen poll and counts the polls and updates after it.
#include "engine/experiment/batch_training.hpp"
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/learning/learner_factory.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace armfarm {
namespace {

/// should_stop that returns true from its `fire_at`-th call on (1-based; 0: never) and counts
/// the calls made after the first true.
struct PollCounter {
  long fire_at = 0;
  long calls = 0;
  long calls_after_stop = 0;
  std::function<bool()> make() {
    return [this] {
      ++calls;
      if (fire_at > 0 && calls > fire_at) ++calls_after_stop;
      return fire_at > 0 && calls >= fire_at;
    };
  }
};

/// 40 samples of a smooth 1-input, 1-output function.
std::vector<Sample> make_line_samples() {
  std::vector<Sample> samples;
  for (int i = 0; i < 40; ++i) {
    const double x = -1.0 + 0.05 * i;
    samples.push_back({Eigen::VectorXd::Constant(1, x), Eigen::VectorXd::Constant(1, std::sin(2.0 * x))});
  }
  return samples;
}

LearningConfig make_three_epochs() {
  LearningConfig config;
  config.mode = LearningMode::batch;
  config.epochs = 3;
  config.train_fraction = 0.75;  // 30 training samples, 10 test samples
  return config;
}

TEST(BatchTraining, AStopInAnEpochEndsTrainingBeforeTheNextUpdate) {
  const LearningConfig config = make_three_epochs();
  const auto learner = make_learner(config, 1, 1, Eigen::VectorXd());
  PollCounter stop;
  stop.fire_at = 45;  // the 15th poll of epoch 2 (30 polls in epoch 1)
  BatchTrainingResult result;
  const PassResult trained = train_in_batch(*learner, make_line_samples(), config, 7, nullptr, {}, stop.make(), result);
  EXPECT_EQ(trained.status, JobStatus::timeout);
  EXPECT_TRUE(result.stopped);
  EXPECT_EQ(trained.message, "stopped during batch training (epoch 2 of 3, 14 of 30 training samples learnt)");
  EXPECT_EQ(learner->n_updates(), 44u);  // one update per poll before the one that fired
  EXPECT_EQ(stop.calls_after_stop, 0);
  EXPECT_EQ(result.same_run_test.count(), 0) << "a stopped training is not scored";
}

TEST(BatchTraining, AStopWhileScoringEndsBeforeTheNextPrediction) {
  const LearningConfig config = make_three_epochs();
  const auto learner = make_learner(config, 1, 1, Eigen::VectorXd());
  PollCounter stop;
  stop.fire_at = 3 * 30 + 4;  // every training poll, then the 4th of the 10 scoring polls
  BatchTrainingResult result;
  const PassResult trained = train_in_batch(*learner, make_line_samples(), config, 7, nullptr, {}, stop.make(), result);
  EXPECT_EQ(trained.status, JobStatus::timeout);
  EXPECT_EQ(trained.message, "stopped during batch training (scoring, 3 of 10 test samples predicted)");
  EXPECT_EQ(learner->n_updates(), 90u);
  EXPECT_EQ(stop.calls_after_stop, 0);
  EXPECT_TRUE(result.test_indices.empty());
}

TEST(BatchTraining, WithoutAStopEveryUpdateAndPredictionIsPolledOnce) {
  const LearningConfig config = make_three_epochs();
  const auto learner = make_learner(config, 1, 1, Eigen::VectorXd());
  PollCounter never;
  BatchTrainingResult result;
  const PassResult trained = train_in_batch(*learner, make_line_samples(), config, 7, nullptr, {}, never.make(), result);
  ASSERT_TRUE(trained.ok()) << trained.message;
  EXPECT_FALSE(result.stopped);
  EXPECT_EQ(never.calls, 3 * 30 + 10);
  EXPECT_EQ(learner->n_updates(), 90u);
  EXPECT_EQ(result.same_run_test.count(), 10);
}

TEST(BatchTraining, AClockCountsEachUpdateAndPredictionAndAddsTheirSecondsToWhatItHeld) {
  const LearningConfig config = make_three_epochs();
  const auto learner = make_learner(config, 1, 1, Eigen::VectorXd());
  LearnerClock clock;  // a clock that already holds an earlier pass's figures
  clock.update_seconds = 1.0, clock.updates = 5;
  clock.predict_seconds = 2.0, clock.predictions = 7;
  BatchTrainingResult result;
  const auto start = std::chrono::steady_clock::now();
  const PassResult trained = train_in_batch(*learner, make_line_samples(), config, 7, &clock, {}, {}, result);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(trained.ok()) << trained.message;
  EXPECT_EQ(clock.updates, 5 + 3 * 30);
  EXPECT_EQ(clock.predictions, 7 + 10);
  // Seconds are added, not overwritten, and never more than the call's own wall time.
  EXPECT_GT(clock.update_seconds, 1.0);
  EXPECT_GT(clock.predict_seconds, 2.0);
  EXPECT_LE((clock.update_seconds - 1.0) + (clock.predict_seconds - 2.0), wall);

  // Stopped in epoch 2 after 44 updates: the clock counts those and no prediction.
  LearnerClock stopped_clock;
  PollCounter stop;
  stop.fire_at = 45;
  const auto stopped_learner = make_learner(config, 1, 1, Eigen::VectorXd());
  BatchTrainingResult stopped;
  EXPECT_EQ(train_in_batch(*stopped_learner, make_line_samples(), config, 7, &stopped_clock, {}, stop.make(), stopped).status,
            JobStatus::timeout);
  EXPECT_EQ(stopped_clock.updates, 44);
  EXPECT_EQ(stopped_clock.predictions, 0);
  EXPECT_EQ(stopped_clock.predict_seconds, 0.0);
}

/// A batch job whose polls are mostly training ones: 2 s sine (200 ticks a pass), 2 collection
/// repeats (400 samples, 300 trained on), 10 epochs: 3000 training polls against about 1000 of
/// its passes (held-out collection, collection, held-out checkpoint, evaluation).
JobConfig make_long_training_job() {
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 2.0;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::batch;
  config.learning.collect_gain_scale = 1.0;
  config.learning.collect_repeats = 2;
  config.learning.epochs = 10;
  return config;
}

/// The result metrics (timing ones excepted) as "name joint checkpoint = value (reason)" lines.
std::vector<std::string> list_result_metrics(const JobOutcome& outcome) {
  std::vector<std::string> lines;
  for (const Metric& metric : outcome.metrics) {
    if (find_metric_info(metric.name).kind != MetricKind::result) continue;
    char value[64] = "null";
    if (metric.value) std::snprintf(value, sizeof value, "%.17g", *metric.value);
    lines.push_back(metric.name + " " + std::to_string(metric.joint.value_or(0)) + " " +
                    std::to_string(metric.checkpoint ? metric.checkpoint->number : -1) + " = " + value + " (" + metric.reason + ")");
  }
  return lines;
}

TEST(BatchTraining, AJobStoppedInTrainingEndsAsStoppedAndItsRerunMatchesAnUninterruptedRun) {
  const ArmModel model = testing::load_lwr3();
  const JobConfig config = make_long_training_job();
  PollCounter counted;
  const JobOutcome uninterrupted = run_experiment(model, config, counted.make());
  ASSERT_EQ(uninterrupted.status, JobStatus::done) << uninterrupted.message;
  ASSERT_GT(counted.calls, 3000);

  // Stop half-way through the job's polls: inside the 3000 training polls.
  PollCounter stop;
  stop.fire_at = counted.calls / 2;
  const JobOutcome stopped = run_experiment(model, config, stop.make());
  EXPECT_EQ(stop.calls_after_stop, 0) << "the job went on after the stop";
  EXPECT_EQ(stopped.status, JobStatus::timeout);
  EXPECT_NE(stopped.message.find("stopped during batch training (epoch "), std::string::npos) << stopped.message;
  EXPECT_NEAR(stopped.end_time, 2 * 2.0, 1e-9) << "the plant time the two collection passes reached";
  for (const Metric& metric : stopped.metrics) {
    EXPECT_NE(metric.name, "same_run_test_nmse") << "a stopped training is not scored";
    EXPECT_NE(metric.name, "tracking_nmse") << "a stopped job runs no evaluation pass";
  }

  // What a resumed sweep does with the stopped job: run it again from its configuration.
  const JobOutcome rerun = run_experiment(model, config);
  ASSERT_EQ(rerun.status, JobStatus::done) << rerun.message;
  const std::vector<std::string> expected = list_result_metrics(uninterrupted);
  EXPECT_GT(expected.size(), 50u);
  EXPECT_EQ(list_result_metrics(rerun), expected);
}

}  // namespace
}  // namespace armfarm
