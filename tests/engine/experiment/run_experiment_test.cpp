// The experiment job end to end on the LWR III (issue: "what must be shown"). Each comparison
// is between two runs of the same plant, so it cannot pass by construction.
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/experiment/tick_recording.hpp"
#include "../physics/test_arms.hpp"
#include "job_metrics.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cstdio>
#include <map>

namespace armfarm {
namespace {

using testing::job_metrics;

JobConfig make_sine_config(double duration) {
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = duration;
  return config;
}

JobConfig make_feedback_config(double gain_scale, double duration) {
  JobConfig config = make_sine_config(duration);
  config.control.mode = ControlMode::feedback;
  config.control.feed_forward = FeedForwardSource::none;
  config.learning.mode = LearningMode::none;
  config.control.gain_scale = gain_scale;
  return config;
}

TEST(RunExperiment, FeedbackTracksTheDefaultSinusoid) {
  const ArmModel model = testing::load_lwr3();
  const JobOutcome outcome = run_experiment(model, make_feedback_config(1.0, 8.0));
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  auto metrics = job_metrics(outcome);
  // The bound stated in sweeps/README.md: full-gain PD alone keeps every joint's tracking nMSE
  // below 0.05 (the shoulder, which carries the arm's weight, sags most).
  for (int joint = 1; joint <= 7; ++joint) EXPECT_LT(metrics["tracking_nmse_j" + std::to_string(joint)], 0.05) << joint;
  EXPECT_LT(metrics["tracking_rmse"], 0.03);
  EXPECT_NEAR(outcome.end_time, 8.0, 1e-9);
  std::printf("feedback, gain 1: tracking nMSE %.4f, rmse %.4f rad, %.0f simulated s per wall s\n", metrics["tracking_nmse"],
              metrics["tracking_rmse"], metrics["sim_seconds_per_wall_second"]);
}

TEST(RunExperiment, BatchLearnedFeedForwardBeatsLowGainFeedback) {
  const ArmModel model = testing::load_lwr3();
  const JobOutcome feedback = run_experiment(model, make_feedback_config(0.2, 8.0));
  JobConfig composite = make_sine_config(8.0);
  composite.control.gain_scale = 0.2;
  composite.learning.mode = LearningMode::batch;
  composite.learning.collect_gain_scale = 1.0;  // the thesis's setup: collect under full-gain feedback
  const JobOutcome learned = run_experiment(model, composite);
  ASSERT_EQ(feedback.status, JobStatus::done) << feedback.message;
  ASSERT_EQ(learned.status, JobStatus::done) << learned.message;
  auto f = job_metrics(feedback), l = job_metrics(learned);
  EXPECT_LT(5.0 * l["tracking_nmse"], f["tracking_nmse"]);
  // The joints that carry the arm's weight (table 6.4 of the thesis: 0.80–0.96).
  for (int joint : {2, 4}) EXPECT_GE(l["ff_fb_ratio_avg_j" + std::to_string(joint)], 0.8) << "joint " << joint;
  EXPECT_LT(l["same_run_test_nmse"], 0.5);
  EXPECT_GT(l["n_receptive_fields"], 0.0);
  // On the held-out variant of the sine (never trained on) the model still carries most of the
  // torque of the weight-bearing joints, and predicts worse than on samples of its own runs.
  EXPECT_LT(l["heldout_test_nmse"], 1.0);
  EXPECT_GT(l["heldout_test_nmse"], l["same_run_test_nmse"]);
  for (int joint : {2, 4}) EXPECT_GE(l["heldout_ff_fb_ratio_avg_j" + std::to_string(joint)], 0.5) << "joint " << joint;
  std::printf("gain 0.2: feedback tracking nMSE %.4f, batch LWPR composite %.5f (%.0fx); ff/fb j2 %.2f j4 %.2f; same-run test nMSE %.3f\n"
              "  held out: test nMSE %.3f, id nMSE %.3f, tracking nMSE %.5f, ff/fb j2 %.2f j4 %.2f\n",
              f["tracking_nmse"], l["tracking_nmse"], f["tracking_nmse"] / l["tracking_nmse"], l["ff_fb_ratio_avg_j2"],
              l["ff_fb_ratio_avg_j4"], l["same_run_test_nmse"], l["heldout_test_nmse"], l["heldout_id_nmse"],
              l["heldout_tracking_nmse"], l["heldout_ff_fb_ratio_avg_j2"], l["heldout_ff_fb_ratio_avg_j4"]);
}

TEST(RunExperiment, OnlineLearningOverRepeatedReachingReducesFeedback) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.reaches = 12;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::online;
  config.recording.series = {"TRIAL"};
  JobConfig feedback = config;
  feedback.control.mode = ControlMode::feedback;
  feedback.learning.mode = LearningMode::none;
  const JobOutcome outcome = run_experiment(model, config);
  const JobOutcome reference = run_experiment(model, feedback);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  ASSERT_EQ(reference.status, JobStatus::done) << reference.message;
  auto metrics = job_metrics(outcome);
  ASSERT_EQ(metrics["n_segments"], 12.0);
  // Mean |fb| per reach (TRIAL column 2) over the last three reaches, learned against feedback
  // alone on the same reaches: the reaches differ in difficulty, so first-against-last alone
  // would measure the draw as much as the learning.
  auto trials_of = [](const JobOutcome& o) -> const Series* {
    for (const Series& series : o.series) if (series.name == "TRIAL") return &series;
    return nullptr;
  };
  const Series* trials = trials_of(outcome);
  const Series* unlearned = trials_of(reference);
  ASSERT_NE(trials, nullptr);
  ASSERT_NE(unlearned, nullptr);
  ASSERT_EQ(trials->rows.rows(), 12);
  const double first = trials->rows.col(2).head(3).mean(), last = trials->rows.col(2).tail(3).mean();
  const double last_feedback = unlearned->rows.col(2).tail(3).mean();
  const double first_reach = trials->rows(0, 2);  // learnt from an empty model
  EXPECT_LT(last, 0.5 * last_feedback);
  EXPECT_LT(last, first_reach);
  std::printf("online reaching, gain 0.2: avg|fb| reach 1 %.3f N·m, first 3 reaches %.3f N·m, last 3 %.3f N·m (feedback alone %.3f), "
              "%g receptive fields\n",
              first_reach, first, last, last_feedback, metrics["n_receptive_fields"]);
}

TEST(RunExperiment, LearnedFeedForwardBeatsTheNominalModelUnderAPayload) {
  const ArmModel model = testing::load_lwr3();
  JobConfig analytic = make_sine_config(20.0);
  analytic.control.gain_scale = 0.2;
  analytic.control.feed_forward = FeedForwardSource::analytic;
  analytic.learning.mode = LearningMode::none;
  analytic.mismatch.payload.mass = 3.0;
  JobConfig learned = analytic;
  learned.control.feed_forward = FeedForwardSource::learner;
  learned.learning.mode = LearningMode::online;
  const JobOutcome a = run_experiment(model, analytic), l = run_experiment(model, learned);
  ASSERT_EQ(a.status, JobStatus::done) << a.message;
  ASSERT_EQ(l.status, JobStatus::done) << l.message;
  auto am = job_metrics(a), lm = job_metrics(l);
  EXPECT_LT(lm["tracking_rmse_last_segment"], am["tracking_rmse_last_segment"]);
  std::printf("3 kg payload, gain 0.2, last period: nominal analytic ff rmse %.4f rad, online LWPR ff %.4f rad\n",
              am["tracking_rmse_last_segment"], lm["tracking_rmse_last_segment"]);
}

TEST(RunExperiment, AbsurdGainsAreRefusedBeforeTheJobRuns) {
  // kd·h/M = 9.75 on the wrist even at dt/100: no PD period within the keys' range is stable.
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_feedback_config(1.0, 4.0);
  config.control.kp = Eigen::VectorXd::Constant(1, 1e5);
  config.control.kd = Eigen::VectorXd::Constant(1, 1e4);
  config.control.limit_torque = false;
  try {
    run_experiment(model, config);
    ADD_FAILURE() << "kp 1e5 ran";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("pd_substeps: \"auto\" finds no stable value up to 100: ", 0), 0u) << message;
    EXPECT_NE(message.find("lower the gains"), std::string::npos) << message;
  }
}

TEST(RunExperiment, TooLowGainsDivergeAndTheMessageSaysWhatToChange) {
  // At gain scale 0.003 the PD cannot hold the LWR III against gravity: it falls, a runaway.
  const ArmModel model = testing::load_lwr3();
  const JobOutcome outcome = run_experiment(model, make_feedback_config(0.003, 2.0));
  EXPECT_EQ(outcome.status, JobStatus::diverged);
  EXPECT_LT(outcome.end_time, 2.0);
  EXPECT_NE(outcome.message.find("raise control.gain_scale (now 0.003)"), std::string::npos) << outcome.message;
  std::printf("gain scale 0.003: %s at t = %.2f s: %s\n", to_string(outcome.status), outcome.end_time, outcome.message.c_str());
}

TEST(RunExperiment, SameConfigAndSeedGiveIdenticalMetrics) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_sine_config(4.0);
  config.control.gain_scale = 0.2;
  config.recording.series = {"TOR", "RF"};
  const JobOutcome first = run_experiment(model, config), second = run_experiment(model, config);
  ASSERT_EQ(first.metrics.size(), second.metrics.size());
  for (std::size_t i = 0; i < first.metrics.size(); ++i) {
    if (find_metric_info(first.metrics[i].name).kind != MetricKind::result) continue;
    EXPECT_EQ(first.metrics[i].name, second.metrics[i].name);
    EXPECT_EQ(first.metrics[i].value, second.metrics[i].value) << first.metrics[i].name;
    EXPECT_EQ(first.metrics[i].reason, second.metrics[i].reason) << first.metrics[i].name;
  }
  ASSERT_EQ(first.series.size(), 2u);
  EXPECT_EQ(first.series[1].rows, second.series[1].rows);
}

TEST(RunExperiment, RecordedTimesReadAsTheirDecimals) {
  // dt = 0.01, one sample in 10 ticks: the time column is 0, 0.1, 0.2, ... and each prints
  // (shortest round trip) as that decimal, not as the plant clock's 0.09999999999999999.
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_feedback_config(1.0, 2.0);
  config.recording.series = {"POS"};
  config.recording.every = 10;
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  ASSERT_EQ(outcome.series.size(), 1u);
  const Series& pos = outcome.series.front();
  ASSERT_EQ(pos.columns.front(), "t");
  ASSERT_GE(pos.rows.rows(), 20);
  for (Eigen::Index r = 0; r < pos.rows.rows(); ++r) {
    // The decimal written out by hand: r tenths.
    const std::string decimal = std::to_string(r / 10) + (r % 10 ? "." + std::to_string(r % 10) : "");
    char text[40];
    const std::string shortest(text, std::to_chars(text, text + sizeof text, pos.rows(r, 0)).ptr);
    EXPECT_EQ(shortest, decimal) << "row " << r;
  }
}

TEST(RunExperiment, SimulatedSecondsAreTicksTimesDtNotASumOfDt) {
  // 200 ticks of 0.01 s: a running sum of dt gives 2.0000000000000013, steps · dt gives 2.
  const ArmModel model = testing::load_lwr3();
  const JobOutcome outcome = run_experiment(model, make_feedback_config(1.0, 2.0));
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  auto metrics = job_metrics(outcome);
  char text[40];
  const std::string shortest(text, std::to_chars(text, text + sizeof text, metrics["simulated_seconds"]).ptr);
  EXPECT_EQ(shortest, "2");
}

TEST(RunExperiment, RecordedTickTimesAreTickNumbersTimesDt) {
  EXPECT_EQ(calc_recorded_tick_time(0.09999999999999999, 0.01), 0.1);
  EXPECT_EQ(calc_recorded_tick_time(0.30000000000000004, 0.01), 0.3);
  EXPECT_EQ(calc_recorded_tick_time(2.9999999999999996, 0.001), 3.0);
  // 1/dt not a whole number: i·dt.
  EXPECT_EQ(calc_recorded_tick_time(7 * 0.0015 + 1e-15, 0.0015), 7 * 0.0015);
}

TEST(RunExperiment, ConfigErrorsNameTheField) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_sine_config(1.0);
  config.active_joints = {2, 9};
  try {
    run_experiment(model, config);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("active_joints[1]"), std::string::npos) << error.what();
  }
}

TEST(RunExperiment, SubsetOfJointsRunsWithTheOthersLocked) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_sine_config(4.0);
  config.active_joints = {2, 4};
  config.control.gain_scale = 0.2;
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  std::vector<int> joints;
  for (const Metric& metric : outcome.metrics) {
    if (metric.name == "tracking_nmse" && metric.joint) joints.push_back(*metric.joint);
  }
  EXPECT_EQ(joints, (std::vector<int>{2, 4}));
}

// Issue 11: a joint whose desired angle does not move has no nMSE (NULL with its reason),
// keeps its RMSE, and the job-level mean leaves it out and says so.
TEST(RunExperiment, ConstantTargetJointHasUndefinedNmseAndIsLeftOutOfTheMean) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_feedback_config(1.0, 2.0);
  config.trajectory.sine.amplitude = Eigen::VectorXd::Constant(7, 0.3);
  config.trajectory.sine.frequency = Eigen::VectorXd::Constant(7, 0.5);
  config.trajectory.sine.amplitude[6] = 0.0;  // joint 7 holds still
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  std::optional<Metric> joint7, rmse7, mean;
  double sum = 0.0;
  int defined = 0;
  for (const Metric& metric : outcome.metrics) {
    if (metric.name == metric_names::tracking_nmse && metric.joint == 7) joint7 = metric;
    if (metric.name == metric_names::tracking_rmse && metric.joint == 7) rmse7 = metric;
    if (metric.name == metric_names::tracking_nmse && !metric.joint) mean = metric;
    if (metric.name == metric_names::tracking_nmse && metric.joint && metric.value) sum += *metric.value, ++defined;
  }
  ASSERT_TRUE(joint7 && rmse7 && mean);
  EXPECT_FALSE(joint7->value.has_value());
  EXPECT_NE(joint7->reason.find("below the nMSE floor"), std::string::npos) << joint7->reason;
  ASSERT_TRUE(rmse7->value.has_value());
  EXPECT_GE(*rmse7->value, 0.0);
  EXPECT_EQ(defined, 6);
  ASSERT_TRUE(mean->value.has_value());
  EXPECT_DOUBLE_EQ(*mean->value, sum / 6.0);
  EXPECT_NE(mean->reason.find("6 of 7 joints"), std::string::npos) << mean->reason;
  EXPECT_NE(mean->reason.find("joint 7"), std::string::npos) << mean->reason;
}

// Every metric the job writes is in the catalog, so the database can explain it.
TEST(RunExperiment, EveryMetricIsCatalogued) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_sine_config(1.0);
  config.learning.mode = LearningMode::batch;
  config.learning.train_fraction = 0.8;
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  for (const Metric& metric : outcome.metrics) {
    EXPECT_NO_THROW(find_metric_info(metric.name)) << metric.name;
    if (!metric.value) { EXPECT_FALSE(metric.reason.empty()) << metric.name; }
  }
}

}  // namespace
}  // namespace armfarm
