// Task tracking over a window of trajectory points (statistics.window, the thesis's table 6.3):
// hand-computed values on a few synthetic ticks, then a real job checked against an independent
// recomputation from its recorded POS / POS_D series.
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/pass_statistics.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "support/test_arms.hpp"
#include "job_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <string>

namespace armfarm {
namespace {

namespace names = metric_names;

ControlCommand make_command(int joints) {
  return ControlCommand{Eigen::VectorXd::Zero(joints), Eigen::VectorXd::Zero(joints), Eigen::VectorXd::Zero(joints),
                        Eigen::Matrix<bool, Eigen::Dynamic, 1>::Constant(joints, false)};
}

ErrorFloors make_floors(int joints) {
  return ErrorFloors{Eigen::VectorXd::Constant(joints, 1e-3), Eigen::VectorXd::Constant(joints, 1e-3), Eigen::Vector3d::Constant(1e-3)};
}

/// Two segments of four ticks (k = 0..3, 4..7): y_d = 0.01·k m, the y error alternates ±1 mm,
/// x and z hold still and are tracked exactly.
PassStatistics run_eight_ticks(StatisticsConfig window) {
  const int joints = 1;
  PassStatistics statistics(joints, 0.0, std::move(window));
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(joints);
  for (int k = 0; k < 8; ++k) {
    if (k == 4) statistics.start_segment(0.04, 0);
    const Eigen::Vector3d desired(0.5, 0.01 * k, 0.6);
    const Eigen::Vector3d actual = desired + Eigen::Vector3d(0.0, k % 2 ? 1e-3 : -1e-3, 0.0);
    statistics.add_tick(q, q, desired, actual, make_command(joints));
  }
  statistics.end(0);
  return statistics;
}

std::map<std::string, Metric> write_all(const PassStatistics& statistics) {
  std::vector<Metric> metrics;
  MetricWriter writer(metrics, {1});
  statistics.write_metrics(writer, make_floors(1));
  std::map<std::string, Metric> by_name;
  for (const Metric& metric : metrics) {
    if (!metric.joint) by_name[metric.name] = metric;
  }
  return by_name;
}

TEST(PassStatisticsWindow, PerSegmentWindowMatchesAHandComputedValue) {
  // Points 2-3 of each segment: ticks 1, 2, 5, 6, y_d = 0.01, 0.02, 0.05, 0.06 m (mean 0.035,
  // population variance (0.025² + 0.015²)·2/4 = 4.25e-4 m²), every squared error 1e-6 m².
  const PassStatistics statistics = run_eight_ticks(StatisticsConfig{{2, 3}, WindowCounting::segment});
  EXPECT_EQ(statistics.window_ticks(), 4);
  const auto metrics = write_all(statistics);
  ASSERT_TRUE(metrics.at(names::window_tracking_nmse_y).value);
  EXPECT_NEAR(*metrics.at(names::window_tracking_nmse_y).value, 1e-6 / 4.25e-4, 1e-12);
  EXPECT_NEAR(*metrics.at(names::window_tracking_rmse_y).value, 1e-3, 1e-15);
  // x and z hold still: no nMSE (NULL with the floor as reason), an exact RMSE of 0.
  EXPECT_FALSE(metrics.at(names::window_tracking_nmse_z).value);
  EXPECT_NE(metrics.at(names::window_tracking_nmse_z).reason.find("below the nMSE floor"), std::string::npos);
  EXPECT_EQ(*metrics.at(names::window_tracking_rmse_z).value, 0.0);
  EXPECT_TRUE(metrics.at(names::window_tracking_rmse_z).reason.empty()) << metrics.at(names::window_tracking_rmse_z).reason;
}

TEST(PassStatisticsWindow, PassWindowCountsAcrossSegments) {
  // Points 2-6 of the pass: ticks 1..5, y_d = 0.01..0.05 m (variance 2e-4 m²), squared error 1e-6.
  const PassStatistics statistics = run_eight_ticks(StatisticsConfig{{2, 6}, WindowCounting::pass});
  EXPECT_EQ(statistics.window_ticks(), 5);
  EXPECT_NEAR(*write_all(statistics).at(names::window_tracking_nmse_y).value, 1e-6 / 2e-4, 1e-12);
}

TEST(PassStatisticsWindow, WindowOverEverythingEqualsTheWholePass) {
  for (const StatisticsConfig& window :
       {StatisticsConfig{{1, 4}, WindowCounting::segment}, StatisticsConfig{{1, 8}, WindowCounting::pass},
        StatisticsConfig{{1, 1000000}, WindowCounting::pass}}) {
    const auto metrics = write_all(run_eight_ticks(window));
    EXPECT_DOUBLE_EQ(*metrics.at(names::window_tracking_nmse_y).value, *metrics.at(names::tracking_nmse_y).value);
    EXPECT_DOUBLE_EQ(*metrics.at(names::window_tracking_rmse_y).value, *metrics.at(names::tracking_rmse_y).value);
  }
}

TEST(PassStatisticsWindow, NoWindowNoMetricsAndAnEmptyWindowSaysWhy) {
  const auto none = write_all(run_eight_ticks(StatisticsConfig{}));
  EXPECT_EQ(none.count(names::window_tracking_nmse_y), 0u);
  const auto empty = write_all(run_eight_ticks(StatisticsConfig{{5, 9}, WindowCounting::segment}));
  ASSERT_EQ(empty.count(names::window_tracking_nmse_y), 1u);
  EXPECT_FALSE(empty.at(names::window_tracking_nmse_y).value);
  EXPECT_FALSE(empty.at(names::window_tracking_rmse_y).value);
  EXPECT_NE(empty.at(names::window_tracking_nmse_y).reason.find("no tick in the window of points 5-9"), std::string::npos)
      << empty.at(names::window_tracking_nmse_y).reason;
  EXPECT_NE(empty.at(names::window_tracking_nmse_y).reason.find("the longest had 4 points"), std::string::npos);
}

TEST(PassStatisticsWindow, ValidationNamesTheKey) {
  const ModelFacts lwr3{7};
  JobConfig config;
  config.statistics.window = {325, 750};
  EXPECT_TRUE(validate(config, lwr3).empty());
  for (const std::vector<int>& bad : {std::vector<int>{325}, std::vector<int>{750, 325}, std::vector<int>{1, 2, 3}, std::vector<int>{0, 5}}) {
    config.statistics.window = bad;
    const std::vector<ConfigProblem> problems = validate(config, lwr3);
    ASSERT_EQ(problems.size(), 1u) << make_problems_text(problems);
    EXPECT_EQ(problems[0].path.rfind("statistics.window", 0), 0u) << problems[0].path;
  }
}

// A real figure-eight job: the window metric against the nMSE recomputed (two-pass, from the
// recorded series) over the same rows, and a window over each whole loop against the pass's.
TEST(PassStatisticsWindow, FigureEightJobMatchesARecomputationFromPosAndPosD) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::figure_eight;
  config.trajectory.figure_eight.points_per_loop = 150;
  config.trajectory.figure_eight.loops = 2;
  config.control.mode = ControlMode::feedback;
  config.control.feed_forward = FeedForwardSource::none;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::none;
  config.recording.series = {"POS", "POS_D"};
  config.statistics.window = {40, 120};
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  const Series* pos = nullptr;
  const Series* pos_d = nullptr;
  for (const Series& series : outcome.series) {
    if (series.name == "POS") pos = &series;
    if (series.name == "POS_D") pos_d = &series;
  }
  ASSERT_TRUE(pos && pos_d);
  ASSERT_EQ(pos->rows.rows(), 300);
  ASSERT_EQ(pos->columns.size(), 4u);  // t, x, y, z
  std::map<std::string, double> metrics = testing::job_metrics(outcome);
  const std::string* nmse[3] = {&names::window_tracking_nmse_x, &names::window_tracking_nmse_y, &names::window_tracking_nmse_z};
  for (int axis : {1, 2}) {  // y, z (x is constant on the eight: undefined)
    double mean = 0.0, squared_error = 0.0;
    int count = 0;
    for (int loop = 0; loop < 2; ++loop) {
      for (int point = 40; point <= 120; ++point) {
        const int row = loop * 150 + point - 1;
        mean += pos_d->rows(row, 1 + axis);
        squared_error += std::pow(pos->rows(row, 1 + axis) - pos_d->rows(row, 1 + axis), 2);
        ++count;
      }
    }
    mean /= count;
    double variance = 0.0;
    for (int loop = 0; loop < 2; ++loop) {
      for (int point = 40; point <= 120; ++point) variance += std::pow(pos_d->rows(loop * 150 + point - 1, 1 + axis) - mean, 2);
    }
    variance /= count;
    const double expected = squared_error / count / variance;
    ASSERT_TRUE(metrics.count(*nmse[axis]) == 1 && !std::isnan(metrics[*nmse[axis]])) << *nmse[axis];
    EXPECT_NEAR(metrics[*nmse[axis]], expected, 1e-9 * expected) << *nmse[axis];
    // The window is a different part of the eight: not the whole-pass figure.
    EXPECT_GT(std::fabs(metrics[*nmse[axis]] / metrics[axis == 1 ? names::tracking_nmse_y : names::tracking_nmse_z] - 1.0), 1e-3);
  }

  config.statistics.window = {1, 150};  // every point of each loop
  const JobOutcome whole = run_experiment(model, config);
  ASSERT_EQ(whole.status, JobStatus::done) << whole.message;
  const std::map<std::string, double> whole_metrics = testing::job_metrics(whole);
  EXPECT_NEAR(whole_metrics.at(names::window_tracking_nmse_y), whole_metrics.at(names::tracking_nmse_y), 1e-12);
  EXPECT_NEAR(whole_metrics.at(names::window_tracking_nmse_z), whole_metrics.at(names::tracking_nmse_z), 1e-12);
  EXPECT_NEAR(whole_metrics.at(names::window_tracking_rmse_z), whole_metrics.at(names::tracking_rmse_z), 1e-15);
}

// The held-out pass scores the same window (heldout_window_*), catalogued like every metric; a
// window over every point of each held-out loop equals the held-out whole-pass figure.
TEST(PassStatisticsWindow, HeldOutPassWritesTheWindowToo) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::figure_eight;
  config.trajectory.figure_eight.points_per_loop = 200;
  config.trajectory.figure_eight.loops = 1;
  config.learning.mode = LearningMode::batch;
  config.learning.collect_repeats = 1;
  config.learning.heldout_segments = 2;
  config.control.gain_scale = 0.2;
  config.statistics.window = {1, 200};
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  std::map<std::string, double> heldout;
  for (const Metric& metric : outcome.metrics) {
    EXPECT_NO_THROW(find_metric_info(metric.name)) << metric.name;
    if (metric.checkpoint && !metric.joint && metric.value) heldout[metric.name] = *metric.value;
  }
  const std::string prefix = names::heldout_prefix;
  ASSERT_EQ(heldout.count(prefix + names::window_tracking_nmse_z), 1u);
  EXPECT_DOUBLE_EQ(heldout[prefix + names::window_tracking_nmse_z], heldout[prefix + names::tracking_nmse_z]);
  EXPECT_DOUBLE_EQ(heldout[prefix + names::window_tracking_rmse_y], heldout[prefix + names::tracking_rmse_y]);
}

}  // namespace
}  // namespace armfarm
