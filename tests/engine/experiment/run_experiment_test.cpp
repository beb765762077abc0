// The experiment job end to end on the LWR III (issue: "what must be shown"). Each comparison
// is between two runs of the same plant, so it cannot pass by construction.
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/experiment/tick_recording.hpp"
#include "support/test_arms.hpp"
#include "job_metrics.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "engine/experiment/job_config_validation.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cstdio>
#include <map>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

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

// ------------------------------------------------------------------------------------------------
// Folded in from engine/experiment/shared_trajectory_test.cpp:
// A job run on a trajectory built beforehand (and shared with another job) gives the same
// outcome, bit for bit, as the job building its own; the trajectory inputs are what decides.

namespace armfarm {
namespace {

/// A short online reaching job on joints 1, 2, 4 with the held-out evaluation on.
JobConfig make_reaching_config() {
  JobConfig config;
  config.active_joints = {1, 2, 4};
  config.seed = 3;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.reaches = 4;
  config.trajectory.reaching.points_per_reach = 60;
  config.learning.mode = LearningMode::online;
  config.learning.heldout = true;
  config.learning.heldout_segments = 2;
  config.recording.series = {"TRIAL", "RF"};
  return config;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_identical(const JobOutcome& a, const JobOutcome& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.message, b.message);
  EXPECT_TRUE(same_bits(a.end_time, b.end_time));
  ASSERT_EQ(a.metrics.size(), b.metrics.size());
  int compared = 0;
  for (std::size_t i = 0; i < a.metrics.size(); ++i) {
    const Metric& x = a.metrics[i];
    const Metric& y = b.metrics[i];
    ASSERT_EQ(x.name, y.name);
    EXPECT_EQ(x.joint, y.joint) << x.name;
    if (find_metric_info(x.name).kind == MetricKind::timing) continue;
    ASSERT_EQ(x.value.has_value(), y.value.has_value()) << x.name;
    if (x.value) { EXPECT_TRUE(same_bits(*x.value, *y.value)) << x.name << ": " << *x.value << " vs " << *y.value; }
    ++compared;
  }
  EXPECT_GT(compared, 30);
  ASSERT_EQ(a.series.size(), b.series.size());
  for (std::size_t s = 0; s < a.series.size(); ++s) {
    ASSERT_EQ(a.series[s].rows.rows(), b.series[s].rows.rows()) << a.series[s].name;
    ASSERT_EQ(a.series[s].rows.cols(), b.series[s].rows.cols()) << a.series[s].name;
    EXPECT_EQ(std::memcmp(a.series[s].rows.data(), b.series[s].rows.data(), sizeof(double) * a.series[s].rows.size()), 0)
        << a.series[s].name;
  }
}

TEST(SharedTrajectory, JobOnASharedBuildIsBitIdenticalToOneThatBuildsItsOwn) {
  const ArmModel model = testing::load_lwr3();
  const JobConfig config = make_reaching_config();
  // The build comes from another job of the sweep: equal trajectory inputs, other gains and LWPR.
  JobConfig other = config;
  other.control.gain_scale = 0.2;
  other.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 2.0);
  const JobTrajectories shared = build_job_trajectories(model, other);
  ASSERT_TRUE(shared.heldout.has_value());
  const JobOutcome rebuilt = run_experiment(model, config);
  const JobOutcome reused = run_experiment(model, config, shared);
  ASSERT_EQ(rebuilt.status, JobStatus::done) << rebuilt.message;
  expect_identical(rebuilt, reused);
  // Shared read-only: a second job on the same build gives the same again.
  expect_identical(rebuilt, run_experiment(model, config, shared));
}

TEST(SharedTrajectory, BuildDependsOnTrajectoryInputsOnly) {
  const ArmModel model = testing::load_lwr3();
  const JobConfig config = make_reaching_config();
  const JobTrajectories base = build_job_trajectories(model, config);
  JobConfig gains = config;
  gains.control.gain_scale = 0.3;
  gains.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 0.5);
  gains.simulation.integrator = IntegratorKind::runge_kutta_merson;
  EXPECT_FALSE(is_trajectory_input("control.gain_scale"));
  EXPECT_FALSE(is_trajectory_input("integrator"));
  EXPECT_EQ(build_job_trajectories(model, gains).training.q, base.training.q);
  JobConfig seed = config;
  seed.seed = 4;
  EXPECT_TRUE(is_trajectory_input("seed"));
  EXPECT_NE(build_job_trajectories(model, seed).training.q, base.training.q);
  JobConfig reaches = config;
  reaches.learning.heldout_segments = 3;
  EXPECT_TRUE(is_trajectory_input("learning.heldout_segments"));
  EXPECT_NE(build_job_trajectories(model, reaches).heldout->q.rows(), base.heldout->q.rows());
  for (const char* path : {"trajectory.kind", "trajectory.reaching.reaches", "dt", "active_joints"}) {
    EXPECT_TRUE(is_trajectory_input(path)) << path;
  }
}

TEST(SharedTrajectory, TrajectoryInputsAreKeys) {
  // Every input the builder reads outside the trajectory block is a real key (no misspelt name
  // that would silently leave a field out of the runner's trajectory key).
  std::set<std::string> inputs;
  for (const JobConfigKey& key : job_config_keys()) {
    if (is_trajectory_input(key.path) && key.path.rfind("trajectory.", 0) != 0) inputs.insert(key.path);
  }
  EXPECT_EQ(inputs, (std::set<std::string>{"dt", "seed", "active_joints", "armature_scale", "end_effector.link", "end_effector.offset", "learning.mode", "learning.heldout",
                                           "learning.heldout_amplitude_scale", "learning.heldout_phase_step",
                                           "learning.heldout_segments", "learning.heldout_recorded_fraction", "start_posture"}));
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from engine/experiment/ssgpr_job_test.cpp:
// A job with learning.learner = "ssgpr": every phase (batch training, the same-run and held-out
// scores, the learner's feed-forward, online learning) drives SSGPR through the Learner
// interface. Compared against feedback alone on the same plant, so it cannot pass by construction.

namespace armfarm {
namespace {

using testing::job_metrics;

// Joints 2 and 4 (6 inputs, 2 outputs) on a 6 s sine at low gains.
JobConfig make_ssgpr_config(LearningMode mode) {
  JobConfig config;
  config.active_joints = {2, 4};
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 6.0;
  config.control.gain_scale = 0.2;
  config.learning.mode = mode;
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 60;
  config.learning.ssgpr.fit_samples = 120;
  config.learning.ssgpr.fit.iterations = 40;
  return config;
}

TEST(SsgprJob, BatchLearnedFeedForwardBeatsLowGainFeedback) {
  const ArmModel model = testing::load_lwr3();
  JobConfig feedback = make_ssgpr_config(LearningMode::none);
  feedback.control.mode = ControlMode::feedback;
  feedback.control.feed_forward = FeedForwardSource::none;
  const JobConfig learned = make_ssgpr_config(LearningMode::batch);
  const JobOutcome f_outcome = run_experiment(model, feedback), l_outcome = run_experiment(model, learned);
  ASSERT_EQ(f_outcome.status, JobStatus::done) << f_outcome.message;
  ASSERT_EQ(l_outcome.status, JobStatus::done) << l_outcome.message;
  auto f = job_metrics(f_outcome), l = job_metrics(l_outcome);
  EXPECT_LT(5.0 * l["tracking_nmse"], f["tracking_nmse"]);
  for (int joint : {2, 4}) EXPECT_GE(l["ff_fb_ratio_avg_j" + std::to_string(joint)], 0.8) << "joint " << joint;
  EXPECT_LT(l["same_run_test_nmse"], 0.1);
  EXPECT_LT(l["heldout_test_nmse"], 1.0);
  EXPECT_EQ(l["n_receptive_fields"], 60.0);  // D
  // The numbers the model stores, counted independently: Ω (D×6), L (F×F), B and W (F×2), the
  // update scratch φ, rotated, gain (F each), y_scaled and error (2 each) and the output scale (2), F = 2D.
  const double F = 120.0;
  EXPECT_EQ(l["learner_memory_bytes"], 8.0 * (60 * 6 + F * F + 2 * F * 2 + 3 * F + 3 * 2));
  EXPECT_GT(l["learner_fit_seconds"], 0.0);
  EXPECT_GT(l["learner_us_per_update"], 0.0);
  std::printf("batch SSGPR D = 60, gain 0.2: tracking nMSE %.5f (feedback %.4f), ff/fb j2 %.2f j4 %.2f, same-run nMSE %.4f, "
              "held-out nMSE %.4f, fit %.2f s, %.1f us/update, %.1f us/predict\n",
              l["tracking_nmse"], f["tracking_nmse"], l["ff_fb_ratio_avg_j2"], l["ff_fb_ratio_avg_j4"], l["same_run_test_nmse"],
              l["heldout_test_nmse"], l["learner_fit_seconds"], l["learner_us_per_update"], l["learner_us_per_predict"]);
}

TEST(SsgprJob, OnlineSsgprIsDeterministicAndUntrustedUntilFitted) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_ssgpr_config(LearningMode::online);
  const JobOutcome first = run_experiment(model, config), second = run_experiment(model, config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  ASSERT_EQ(first.metrics.size(), second.metrics.size());
  for (std::size_t i = 0; i < first.metrics.size(); ++i) {
    if (find_metric_info(first.metrics[i].name).kind != MetricKind::result) continue;
    EXPECT_EQ(first.metrics[i].name, second.metrics[i].name);
    EXPECT_EQ(first.metrics[i].value, second.metrics[i].value) << first.metrics[i].name;
  }
  auto m = job_metrics(first);
  // 600 ticks, the first 120 kept for the fit: feed-forward untrusted (0) on at least those.
  for (int joint : {2, 4}) {
    const double untrusted = m["ff_untrusted_fraction_j" + std::to_string(joint)];
    EXPECT_GE(untrusted, 120.0 / 600.0 - 1e-12) << joint;
    EXPECT_LT(untrusted, 0.5) << joint;
  }
  // A seed of the frequency draw alone changes the learnt model, hence the scores.
  config.learning.ssgpr.params.seed = 2;
  auto other = job_metrics(run_experiment(model, config));
  EXPECT_NE(other["heldout_test_nmse"], m["heldout_test_nmse"]);
  EXPECT_NE(other["tracking_nmse"], m["tracking_nmse"]);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from engine/experiment/stored_model_test.cpp:
// Learned models as results (issue 12): a job returns its learner's model file, and a second job
// started from that file predicts exactly what the first predicted at its end.

namespace armfarm {
namespace {

std::map<std::string, double> checkpoint_metrics(const JobOutcome& outcome, std::int64_t checkpoint) {
  std::map<std::string, double> metrics;
  for (const Metric& metric : outcome.metrics) {
    if (!metric.checkpoint || metric.checkpoint->number != checkpoint || !metric.value) continue;
    metrics[metric.joint ? metric.name + "_j" + std::to_string(*metric.joint) : metric.name] = *metric.value;
  }
  return metrics;
}

// Two joints learnt online over two periods of the default sine: a few seconds of simulation.
JobConfig make_online_config() {
  JobConfig config;
  config.active_joints = {2, 4};
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 8.0;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::online;
  config.learning.store_model = true;
  return config;
}

TEST(StoredModel, AFrozenSecondJobPredictsExactlyWhatTheFirstPredictedAtItsEnd) {
  const ArmModel arm = testing::load_lwr3();
  const JobConfig first_config = make_online_config();
  const JobOutcome first = run_experiment(arm, first_config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  ASSERT_FALSE(first.model_file.empty());
  const auto learnt = decode_learner_model(first.model_file);
  ASSERT_GT(learnt->size(), 0u);
  ASSERT_GT(learnt->n_updates(), 0u);

  JobConfig second_config = first_config;
  second_config.learning.mode = LearningMode::frozen;
  second_config.learning.initial_model = "first job";
  second_config.learning.initial_model_bytes = first.model_file;
  const JobOutcome second = run_experiment(arm, second_config);
  ASSERT_EQ(second.status, JobStatus::done) << second.message;
  // Frozen: the model the second job ends with is, byte for byte, the one it started from.
  EXPECT_EQ(second.model_file, first.model_file);

  // The held-out set is the same realisation in both jobs (same trajectory and seed). The first
  // job scored it with its learner in memory at the end of learning (checkpoint = all periods),
  // the second with the learner decoded from the file before its pass (checkpoint 0): every
  // held-out figure must agree exactly.
  std::int64_t last = 0;
  for (const Metric& m : first.metrics) {
    if (m.checkpoint) last = std::max(last, m.checkpoint->number);
  }
  const auto a = checkpoint_metrics(first, last), b = checkpoint_metrics(second, 0);
  ASSERT_GT(a.count("heldout_test_nmse"), 0u);
  ASSERT_GT(a.count("heldout_tracking_nmse"), 0u);
  for (const char* name : {"heldout_test_nmse", "heldout_tracking_nmse", "heldout_ff_fb_ratio_avg_j2", "heldout_ff_fb_ratio_avg_j4",
                           "heldout_learner_updates", "heldout_n_receptive_fields"}) {
    ASSERT_GT(a.count(name), 0u) << name;
    ASSERT_GT(b.count(name), 0u) << name;
    EXPECT_EQ(a.at(name), b.at(name)) << name;
  }
  EXPECT_EQ(b.at("heldout_learner_updates"), static_cast<double>(learnt->n_updates()));
  std::printf("stored model: %zu fields, %llu updates, %zu bytes; held-out test nMSE %.4g in both jobs\n", learnt->size(),
              static_cast<unsigned long long>(learnt->n_updates()), first.model_file.size(), a.at("heldout_test_nmse"));
}

TEST(StoredModel, AnOnlineJobContinuesLearningFromTheStoredModel) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 4.0;
  const JobOutcome first = run_experiment(arm, config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  JobConfig again = config;
  again.learning.initial_model = "first job";
  again.learning.initial_model_bytes = first.model_file;
  const JobOutcome second = run_experiment(arm, again);
  ASSERT_EQ(second.status, JobStatus::done) << second.message;
  const auto a = decode_learner_model(first.model_file), b = decode_learner_model(second.model_file);
  // The second job's learner started with the first one's samples: it learnt the same pass again.
  EXPECT_EQ(b->n_updates(), 2 * a->n_updates());
}

// learning.learn_during_evaluation: a batch learner keeps learning in the evaluation pass, one
// update per tick of the training trajectory; without it the pass leaves the learner as trained
// (epochs × n_training_samples updates, counted independently from the metrics).
TEST(StoredModel, ABatchLearnerLearnsInTheEvaluationPassOnlyWhenAsked) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.mode = LearningMode::batch;
  config.learning.heldout = false;
  config.trajectory.sine.duration = 2.0;
  const JobOutcome trained = run_experiment(arm, config);
  ASSERT_EQ(trained.status, JobStatus::done) << trained.message;
  JobConfig learning = config;
  learning.learning.learn_during_evaluation = true;
  const JobOutcome still_learning = run_experiment(arm, learning);
  ASSERT_EQ(still_learning.status, JobStatus::done) << still_learning.message;

  const auto a = decode_learner_model(trained.model_file), b = decode_learner_model(still_learning.model_file);
  const auto metrics = job_metrics(trained);
  const double training_samples = metrics.at("n_training_samples");
  ASSERT_GT(training_samples, 0.0);
  EXPECT_EQ(static_cast<double>(a->n_updates()), config.learning.epochs * training_samples);
  const auto ticks = static_cast<std::uint64_t>(build_job_trajectories(arm, config).training.size());
  EXPECT_EQ(b->n_updates(), a->n_updates() + ticks);
  // Both evaluations start from the same trained learner: the batch figures agree.
  EXPECT_EQ(job_metrics(still_learning).at("same_run_test_nmse"), metrics.at("same_run_test_nmse"));
}

// An SSGPR job that fits its hyperparameters on its first samples stores the fitted model (on main
// it failed after its whole simulation: the model-file dispatch had no case for that learner).
TEST(StoredModel, AnSsgprJobThatFitsItsHyperparametersStoresTheFittedModel) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 2.0;
  config.control.gain_scale = 1.0;  // full-gain feedback while the learner waits for its fit batch
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 20;
  config.learning.ssgpr.fit_samples = 40;
  config.learning.ssgpr.fit.iterations = 5;
  ASSERT_TRUE(validate(config, ModelFacts{7}).empty());
  const JobOutcome outcome = run_experiment(arm, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  ASSERT_EQ(find_learner_model_kind(outcome.model_file), "ssgpr");
  const auto learnt = decode_learner_model(outcome.model_file);
  EXPECT_EQ(learnt->size(), 20u);
  EXPECT_GT(learnt->n_updates(), 40u);  // the fit batch and every sample after it
  EXPECT_EQ(learnt->input_dim(), 6);
}

TEST(StoredModel, ValidationRefusesAModelOfTheWrongSizeAndAFrozenJobWithoutOne) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 2.0;
  const JobOutcome two_joints = run_experiment(arm, config);
  ASSERT_EQ(two_joints.status, JobStatus::done) << two_joints.message;

  JobConfig three = config;
  three.active_joints = {1, 2, 4};
  three.learning.initial_model = "two.lwpr";
  three.learning.initial_model_bytes = two_joints.model_file;
  std::vector<ConfigProblem> problems = validate(three, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "learning.initial_model");
  EXPECT_NE(problems[0].message.find("maps 6 inputs to 2 outputs"), std::string::npos) << problems[0].message;

  JobConfig corrupt = config;
  corrupt.learning.initial_model = "bad.lwpr";
  corrupt.learning.initial_model_bytes = two_joints.model_file;
  corrupt.learning.initial_model_bytes[corrupt.learning.initial_model_bytes.size() / 2] ^= 0x5a;
  problems = validate(corrupt, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].message.find("checksum"), std::string::npos) << problems[0].message;

  JobConfig frozen = config;
  frozen.learning.mode = LearningMode::frozen;
  problems = validate(frozen, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "learning.mode");
}

}  // namespace
}  // namespace armfarm
