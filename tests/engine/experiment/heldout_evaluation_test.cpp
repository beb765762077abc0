// Held-out evaluation (issue 12): held-out data shares no sample with the training data, and the
// learner is frozen while it is evaluated on the held-out set. Collection repeats:
// collection_pass_test.cpp.
#include "engine/experiment/collection_pass.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/learning/learner_factory.hpp"
#include "support/learning_job.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

namespace armfarm {
namespace {

/// Smallest distance between a row of `a` and a row of `b` (0 when they share a row).
double calc_min_row_distance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    best = std::min(best, (b.rowwise() - a.row(i)).rowwise().norm().minCoeff());
  }
  return best;
}

Eigen::MatrixXd stack_states(const JointTrajectory& t) {
  Eigen::MatrixXd x(t.size(), 3 * t.q.cols());
  x << t.q, t.qd, t.qdd;
  return x;
}

Eigen::MatrixXd stack_inputs(const std::vector<Sample>& samples, std::size_t begin = 0, std::size_t end = ~std::size_t{0}) {
  end = std::min(end, samples.size());
  Eigen::MatrixXd x(static_cast<Eigen::Index>(end - begin), samples.front().x.size());
  for (std::size_t i = begin; i < end; ++i) x.row(static_cast<Eigen::Index>(i - begin)) = samples[i].x.transpose();
  return x;
}

using test_support::make_learning_config;

TEST(HeldoutEvaluation, HeldOutTrajectoriesShareNoSampleWithTraining) {
  const ArmModel model = testing::load_lwr3();
  for (TrajectoryKind kind : {TrajectoryKind::sine, TrajectoryKind::figure_eight, TrajectoryKind::reaching}) {
    const JobConfig config = make_learning_config(kind);
    JobSetup setup(model, config);
    const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
    ASSERT_TRUE(trajectories.heldout.has_value());
    const double distance = calc_min_row_distance(stack_states(*trajectories.heldout), stack_states(trajectories.training));
    EXPECT_GT(distance, 1e-3) << "kind " << static_cast<int>(kind);
    std::printf("kind %d: %d training and %d held-out samples, nearest (q, qd, qdd) pair %.3g apart\n", static_cast<int>(kind),
                trajectories.training.size(), trajectories.heldout->size(), distance);
  }
}

TEST(HeldoutEvaluation, RecordedMotionHoldsOutItsLastPart) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::recorded);
  RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  recorded.task_space = false;
  recorded.loops = 2;
  recorded.filter = RecordedFilter::none;
  recorded.samples.resize(400, 2);
  for (int i = 0; i < 400; ++i) recorded.samples.row(i) << 0.3 * std::sin(0.01 * i), 1.0 + 0.2 * (0.01 * i) * (0.01 * i);
  JobSetup setup(model, config);
  const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  ASSERT_TRUE(trajectories.heldout.has_value());
  EXPECT_EQ(trajectories.heldout->size(), 100);
  EXPECT_EQ(trajectories.training.size(), 2 * 300);
  EXPECT_GT(calc_min_row_distance(trajectories.heldout->q, trajectories.training.q), 1e-4);
  // The held-out part is the recording's last quarter, unchanged.
  EXPECT_NEAR(trajectories.heldout->q(0, 0), recorded.samples(300, 0), 1e-12);
}

TEST(HeldoutEvaluation, HeldOutSamplesShareNoSampleWithTrainingSamples) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::sine);
  config.learning.collect_repeats = 2;
  JobSetup setup(model, config);
  JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  ArmSimulation plant = setup.make_plant();
  std::vector<Sample> training;
  ASSERT_TRUE(collect_samples(setup, plant, CollectionPlan{&trajectories.training, 2, "collection"}, training, {}).ok());
  HeldoutEvaluation heldout(setup, std::move(*trajectories.heldout), {});
  ASSERT_TRUE(heldout.collect_test_samples().ok());
  ASSERT_EQ(training.size(), 2u * 400u);
  ASSERT_EQ(heldout.test_samples().size(), 800u);  // 2 periods of the 0.25 Hz variant
  const double distance = calc_min_row_distance(stack_inputs(heldout.test_samples()), stack_inputs(training));
  EXPECT_GT(distance, 1e-3);
  std::printf("nearest held-out / training sample pair: %.3g apart in (q, qd, qdd)\n", distance);
}

TEST(HeldoutEvaluation, LeavesTheLearnerFrozen) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::sine);
  config.learning.mode = LearningMode::online;
  JobSetup setup(model, config);
  JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  std::unique_ptr<Learner> learner = make_learner(config.learning, 6, 2, calc_trajectory_input_scale(trajectories.training));
  ArmSimulation plant = setup.make_plant();
  std::vector<Sample> samples;
  ASSERT_TRUE(collect_samples(setup, plant, CollectionPlan{&trajectories.training, 1, "collection"}, samples, {}).ok());
  for (const Sample& sample : samples) learner->update(sample.x, sample.y);
  HeldoutEvaluation heldout(setup, std::move(*trajectories.heldout), {});
  ASSERT_TRUE(heldout.collect_test_samples().ok());
  const std::uint64_t updates = learner->n_updates();
  const std::size_t fields = learner->size();
  ASSERT_EQ(updates, samples.size());
  std::vector<Metric> first, second;
  ASSERT_TRUE(heldout.evaluate(*learner, 1, first).ok());
  EXPECT_EQ(learner->n_updates(), updates);
  EXPECT_EQ(learner->size(), fields);
  ASSERT_TRUE(heldout.evaluate(*learner, 2, second).ok());
  // A second evaluation of the unchanged learner measures the same figures.
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].name, second[i].name);
    ASSERT_TRUE(first[i].checkpoint && second[i].checkpoint) << first[i].name;
    EXPECT_EQ(first[i].checkpoint->number, 1);
    EXPECT_EQ(second[i].checkpoint->number, 2);
    // The prediction figures are exact; the control pass repeats up to the integrator's last bits.
    ASSERT_EQ(first[i].value.has_value(), second[i].value.has_value()) << first[i].name;
    if (!first[i].value) continue;
    if (first[i].name.rfind("heldout_test_", 0) == 0 || first[i].name == "heldout_learner_updates") {
      EXPECT_EQ(*first[i].value, *second[i].value) << first[i].name;
    } else {
      EXPECT_NEAR(*first[i].value, *second[i].value, 1e-9 * (1.0 + std::fabs(*first[i].value))) << first[i].name;
    }
  }
}

std::map<std::string, double> metrics_by_key(const JobOutcome& outcome) {
  std::map<std::string, double> metrics;
  for (const Metric& metric : outcome.metrics) {
    std::string key = metric.name;
    if (metric.joint) key += "_j" + std::to_string(*metric.joint);
    if (metric.checkpoint) key += "@" + std::to_string(metric.checkpoint->number);
    metrics[key] = metric.value.value_or(std::nan(""));
  }
  return metrics;
}

TEST(HeldoutEvaluation, OnlineCheckpointsEvaluateWithLearningFrozen) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::reaching);
  config.learning.mode = LearningMode::online;
  config.trajectory.reaching.reaches = 4;
  config.trajectory.reaching.points_per_reach = 50;
  config.learning.heldout_checkpoints = {0, 2, 4};
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  auto m = metrics_by_key(outcome);
  // At checkpoint c the learner has learnt exactly the c reaches of the learning pass, tick by tick.
  const int points = config.trajectory.reaching.points_per_reach;
  EXPECT_EQ(m["heldout_learner_updates@0"], 0.0);
  EXPECT_EQ(m["heldout_learner_updates@2"], 2.0 * points);
  EXPECT_EQ(m["heldout_learner_updates@4"], 4.0 * points);
  EXPECT_EQ(m.count("heldout_learner_updates@1"), 0u);
  EXPECT_EQ(m["heldout_diverged@4"], 0.0);
  // Learning helps on reaches it never saw.
  EXPECT_LT(m["heldout_test_nmse@4"], m["heldout_test_nmse@0"]);
  EXPECT_TRUE(m.count("heldout_ff_fb_ratio_avg_j2@4"));
  EXPECT_TRUE(m.count("heldout_tracking_nmse@2"));
  // The held-out passes change nothing in the learning pass: the same job without them
  // reports the same learning-pass figures.
  JobConfig without = config;
  without.learning.heldout = false;
  auto w = metrics_by_key(run_experiment(model, without));
  for (const char* key : {"tracking_nmse", "ff_fb_ratio_avg_j2", "id_nmse", "n_receptive_fields", "fb_abs_avg_last_segment"}) {
    EXPECT_EQ(m[key], w[key]) << key;
  }
  EXPECT_EQ(w.count("heldout_test_nmse@4"), 0u);
  std::printf("online reaching: held-out test nMSE %.3f before learning, %.3f after 2 reaches, %.3f after 4; "
              "held-out tracking nMSE %.4f -> %.4f\n",
              m["heldout_test_nmse@0"], m["heldout_test_nmse@2"], m["heldout_test_nmse@4"], m["heldout_tracking_nmse@0"],
              m["heldout_tracking_nmse@4"]);
}

// Figures 6.8-6.10 draw the torques of the held-out passes: a `heldout_` series name records its
// signal in every held-out control pass, one series per checkpoint, and the recorded torques are
// the ones the pass's metrics average (checked against heldout_ff_abs_avg / heldout_fb_abs_avg).
TEST(HeldoutEvaluation, HeldOutPassesRecordTheirTorquesPerCheckpoint) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::reaching);
  config.learning.mode = LearningMode::online;
  config.trajectory.reaching.reaches = 2;
  config.trajectory.reaching.points_per_reach = 40;
  config.learning.heldout_checkpoints = {0, 2};
  JobConfig recording = config;
  recording.recording.series = {"TRIAL", "heldout_F", "heldout_FF", "heldout_TOR"};
  const JobOutcome outcome = run_experiment(model, recording);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  std::map<std::string, const Series*> series;
  for (const Series& s : outcome.series) series[s.name] = &s;
  for (const char* name : {"F", "FF", "TOR"}) EXPECT_EQ(series.count(name), 0u) << name << " is not recorded in the learning pass";
  EXPECT_EQ(series.count("TRIAL"), 1u);
  const auto m = metrics_by_key(outcome);
  for (int checkpoint : {0, 2}) {
    const std::string suffix = "_c" + std::to_string(checkpoint);
    for (const char* name : {"heldout_F", "heldout_FF", "heldout_TOR"}) ASSERT_EQ(series.count(name + suffix), 1u) << name << suffix;
    const Series& feedback = *series.at("heldout_F" + suffix);
    const Series& feed_forward = *series.at("heldout_FF" + suffix);
    ASSERT_EQ(feedback.columns.size(), 8u);  // t and the seven joints
    EXPECT_EQ(feedback.columns[1], "j1");
    ASSERT_GT(feedback.rows.rows(), 2);
    // Time from the pass's start, one row per tick.
    EXPECT_EQ(feedback.rows(0, 0), 0.0);
    EXPECT_DOUBLE_EQ(feedback.rows(1, 0), config.simulation.dt);
    EXPECT_EQ(feed_forward.rows.rows(), feedback.rows.rows());
    for (int j = 1; j <= 7; ++j) {
      const std::string at = "_j" + std::to_string(j) + "@" + std::to_string(checkpoint);
      const double ff = feed_forward.rows.col(j).cwiseAbs().mean();
      const double fb = feedback.rows.col(j).cwiseAbs().mean();
      EXPECT_NEAR(ff, m.at("heldout_ff_abs_avg" + at), 1e-9 * (1.0 + ff)) << at;
      EXPECT_NEAR(fb, m.at("heldout_fb_abs_avg" + at), 1e-9 * (1.0 + fb)) << at;
    }
  }
  // The learnt feed-forward grows from checkpoint 0 (nothing learnt) to 2: the series differ.
  EXPECT_LT(series.at("heldout_FF_c0")->rows.rightCols(7).cwiseAbs().mean(), series.at("heldout_FF_c2")->rows.rightCols(7).cwiseAbs().mean());
  // Recording changes no metric.
  const auto plain = metrics_by_key(run_experiment(model, config));
  for (const char* key : {"heldout_ff_fb_ratio_avg_j2@2", "heldout_tracking_nmse@2", "heldout_test_nmse@2", "tracking_nmse"}) {
    EXPECT_EQ(m.at(key), plain.at(key)) << key;
  }
}

TEST(HeldoutEvaluation, CheckpointsOutOfOrderNameTheField) {
  JobConfig config = make_learning_config(TrajectoryKind::sine);
  config.learning.heldout_checkpoints = {3, 2, -1};
  const std::vector<ConfigProblem> problems = validate(config, ModelFacts{7});
  std::set<std::string> paths;
  for (const ConfigProblem& problem : problems) paths.insert(problem.path);
  EXPECT_TRUE(paths.count("learning.heldout_checkpoints[1]")) << make_problems_text(problems);
  EXPECT_TRUE(paths.count("learning.heldout_checkpoints[2]")) << make_problems_text(problems);
}

TEST(HeldoutEvaluation, CheckpointsBeyondTheRunNameTheField) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_learning_config(TrajectoryKind::sine);
  config.learning.heldout_checkpoints = {1, 9};  // batch: epochs, and the job trains 5
  try {
    run_experiment(model, config);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("learning.heldout_checkpoints[1]"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace armfarm
