// Regression checks: verdicts by direction and tolerance. `armfarm compare` through the command
// line: tests/runner/cli/cmd_compare_test.cpp.
#include "analysis/analysis_error.hpp"
#include "analysis/comparison.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

JobResult make_job(const std::string& key, std::map<MetricId, double> metrics, const std::string& status = "done") {
  JobResult job;
  job.key = key;
  job.status = status;
  job.metrics = std::move(metrics);
  return job;
}

MetricInfoTable make_info() {
  MetricInfoTable info;
  for (const MetricInfoRecord& record : testing::make_test_metric_info()) info[record.name] = record;
  return info;
}

const MetricComparison& find(const ComparisonReport& report, const std::string& name) {
  for (const MetricComparison& m : report.metrics) {
    if (m.metric.name == name) return m;
  }
  throw std::runtime_error("no comparison of " + name);
}

TEST(Comparison, DirectionDecidesBetweenImprovementAndRegression) {
  const std::vector<JobResult> base = {make_job("a", {{{"tracking_nmse", 1}, 0.010}, {{"ff_fb_ratio_avg", 1}, 0.80}})};
  const std::vector<JobResult> better = {make_job("a", {{{"tracking_nmse", 1}, 0.008}, {{"ff_fb_ratio_avg", 1}, 0.90}})};
  const std::vector<JobResult> worse = {make_job("a", {{{"tracking_nmse", 1}, 0.012}, {{"ff_fb_ratio_avg", 1}, 0.70}})};
  ToleranceTable tolerances;
  tolerances.defaults.rtol = 0.05;
  const auto improved = compare_results(base, better, tolerances, {}, make_info());
  EXPECT_EQ(find(improved, "tracking_nmse").verdict, ChangeVerdict::improved);
  EXPECT_EQ(find(improved, "ff_fb_ratio_avg").verdict, ChangeVerdict::improved);
  EXPECT_FALSE(improved.regressed());
  const auto regressed = compare_results(base, worse, tolerances, {}, make_info());
  EXPECT_EQ(find(regressed, "tracking_nmse").verdict, ChangeVerdict::regressed);
  EXPECT_EQ(find(regressed, "ff_fb_ratio_avg").verdict, ChangeVerdict::regressed);
  EXPECT_NEAR(find(regressed, "tracking_nmse").relative_change, 0.2, 1e-12);
  EXPECT_TRUE(regressed.regressed());
  tolerances.defaults.rtol = 0.5;  // wide enough: within tolerance
  EXPECT_FALSE(compare_results(base, worse, tolerances, {}, make_info()).regressed());
}

TEST(Comparison, TimingsAreIgnoredAndMissingJobsReported) {
  const std::vector<JobResult> base = {make_job("a", {{{"learner_us_per_update", {}}, 10.0}}), make_job("b", {}),
                                       make_job("c", {{{"test_nmse", 1}, 0.1}})};
  const std::vector<JobResult> next = {make_job("a", {{{"learner_us_per_update", {}}, 30.0}}), make_job("d", {}),
                                       make_job("c", {{{"test_nmse", 1}, 0.1}}, "diverged")};
  const auto report = compare_results(base, next, ToleranceTable{}, {}, make_info());
  EXPECT_TRUE(report.metrics.empty());  // timing left out; c is not done in new
  EXPECT_EQ(report.only_in_base, std::vector<std::string>{"b"});
  EXPECT_EQ(report.only_in_next, std::vector<std::string>{"d"});
  ASSERT_EQ(report.status_changes.size(), 1u);
  EXPECT_EQ(report.status_changes[0].next_status, "diverged");
  EXPECT_TRUE(report.regressed());
}

TEST(Comparison, TolerancesFilePerMetricAndJoint) {
  const ToleranceTable table = parse_tolerances(
      R"({"default": {"rtol": 0.01}, "metrics": {"tracking_nmse": {"rtol": 0.1, "joints": {"2": {"atol": 1.0}}},
          "learner_us_per_update": {"direction": "lower", "rtol": 0.5}}})",
      "tol.json", Tolerance{});
  EXPECT_DOUBLE_EQ(table.find(MetricId{"test_nmse", 1}).rtol, 0.01);
  EXPECT_DOUBLE_EQ(table.find(MetricId{"tracking_nmse", 1}).rtol, 0.1);
  EXPECT_DOUBLE_EQ(table.find(MetricId{"tracking_nmse", 2}).atol, 1.0);
  EXPECT_DOUBLE_EQ(table.find(MetricId{"tracking_nmse", 2}).rtol, 0.1);  // inherited from the metric
  const std::vector<JobResult> base = {make_job("a", {{{"learner_us_per_update", {}}, 10.0}})};
  const std::vector<JobResult> next = {make_job("a", {{{"learner_us_per_update", {}}, 30.0}})};
  EXPECT_TRUE(compare_results(base, next, table, {}, make_info()).metrics.empty());  // timing: left out
  const auto shown = compare_results(base, next, table, {}, make_info(), true);     // --timing: shown, not gating
  ASSERT_EQ(shown.metrics.size(), 1u);
  EXPECT_EQ(shown.metrics[0].verdict, ChangeVerdict::changed);
  EXPECT_FALSE(shown.regressed());
  try {
    parse_tolerances(R"({"metrics": {"tracking_nmse": {"rtol": "wide"}}})", "tol.json", Tolerance{});
    FAIL() << "expected an error";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("tol.json: metrics.tracking_nmse.rtol"), std::string::npos) << e.what();
  }
}

// Issue 11: the catalog (metric_info) says torque saturation is lower-is-better, so tripling it
// is a regression; a metric without a direction is reported as changed, not judged.
TEST(Comparison, TripledTorqueSaturationIsARegressionAndNoDirectionIsReportedAsSuch) {
  const std::vector<JobResult> base = {
      make_job("a", {{{"torque_saturation_fraction", 2}, 0.01}, {{"n_receptive_fields", {}}, 100}})};
  const std::vector<JobResult> next = {
      make_job("a", {{{"torque_saturation_fraction", 2}, 0.03}, {{"n_receptive_fields", {}}, 140}})};
  const auto report = compare_results(base, next, ToleranceTable{}, {}, make_info());
  EXPECT_EQ(find(report, "torque_saturation_fraction").verdict, ChangeVerdict::regressed);
  EXPECT_EQ(find(report, "n_receptive_fields").verdict, ChangeVerdict::changed);
  EXPECT_EQ(find(report, "n_receptive_fields").direction, BetterDirection::none);
  EXPECT_TRUE(report.regressed());
  EXPECT_NE(format_comparison(report, false, false).find("| none | changed |"), std::string::npos);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from analysis/comparison_pairing_test.cpp:
// Compare what users mean: jobs that differ only in what they record pair; --pair-by pairs by a
// chosen subset of parameters, refuses an ambiguous pairing naming what tells the jobs apart,
// refuses recording keys and unknown parameters.

namespace armfarm {
namespace {

JobResult make_job(const std::string& key, double gain, const std::string& mode, int seed, double nmse,
                   const nlohmann::json& series = {"TRIAL"}) {
  JobResult job;
  job.key = key;
  job.status = "done";
  job.seed = seed;
  job.config = {{"control", {{"gain_scale", gain}}},
                {"learning", {{"mode", mode}}},
                {"seed", seed},
                {"recording", {{"series", series}, {"every", 10}}}};
  job.params = {{"control.gain_scale", gain}};
  job.metrics = {{{"tracking_nmse", 1}, nmse}};
  return job;
}

TEST(ComparisonPairing, JobsThatDifferOnlyInWhatTheyRecordPair) {
  const std::vector<JobResult> base = {make_job("a1", 0.2, "online", 0, 0.01), make_job("a2", 1.0, "online", 0, 0.02)};
  const std::vector<JobResult> next = {make_job("b1", 0.2, "online", 0, 0.01, {"TRIAL", "RF", "PHI"}),
                                       make_job("b2", 1.0, "online", 0, 0.03, {"RF"})};
  const ComparisonReport report = compare_results(base, next, {}, {}, make_info());
  EXPECT_EQ(report.jobs_paired, 2);
  EXPECT_TRUE(report.only_in_base.empty());
  EXPECT_TRUE(report.only_in_next.empty());
  ASSERT_EQ(report.metrics.size(), 2u);
  EXPECT_EQ(report.metrics[1].key, "a2");
  EXPECT_EQ(report.metrics[1].next_key, "b2");
  EXPECT_EQ(report.metrics[1].verdict, ChangeVerdict::regressed);  // 0.02 -> 0.03, lower is better
  // A computed difference (the learning mode) still keeps them apart.
  const std::vector<JobResult> batch = {make_job("c1", 0.2, "batch", 0, 0.01)};
  const ComparisonReport apart = compare_results(base, batch, {}, {}, make_info());
  EXPECT_EQ(apart.jobs_paired, 0);
  EXPECT_EQ(apart.only_in_base.size(), 2u);
  EXPECT_EQ(apart.only_in_next, std::vector<std::string>{"c1"});
}

TEST(ComparisonPairing, PairByAChosenSubsetOfParameters) {
  const std::vector<JobResult> base = {make_job("a1", 0.2, "online", 0, 0.010), make_job("a2", 1.0, "online", 0, 0.020)};
  const std::vector<JobResult> next = {make_job("b2", 1.0, "batch", 0, 0.010), make_job("b1", 0.2, "batch", 0, 0.005)};
  const ComparisonReport report = compare_results(base, next, {}, {}, make_info(), false, PairingRule{{"control.gain_scale"}});
  EXPECT_EQ(report.jobs_paired, 2);
  EXPECT_EQ(report.pair_by, std::vector<std::string>{"control.gain_scale"});
  ASSERT_EQ(report.metrics.size(), 2u);
  EXPECT_EQ(report.metrics[0].key, "a1");
  EXPECT_EQ(report.metrics[0].next_key, "b1");
  EXPECT_DOUBLE_EQ(report.metrics[0].next, 0.005);
  EXPECT_EQ(report.metrics[1].next_key, "b2");
  EXPECT_FALSE(report.regressed());  // batch is better at both gains
  EXPECT_NE(format_comparison(report, false, false).find("Compared 2 jobs paired by control.gain_scale, 2 metrics"),
            std::string::npos)
      << format_comparison(report, false, false);
  EXPECT_EQ(nlohmann::json::parse(format_comparison(report, true, false))["metrics"][0]["new_key"], "b1");
}

TEST(ComparisonPairing, AnAmbiguousPairingNamesWhatTellsTheJobsApart) {
  const std::vector<JobResult> base = {make_job("a1", 0.2, "online", 0, 0.010)};
  const std::vector<JobResult> next = {make_job("b1", 0.2, "batch", 0, 0.010), make_job("b2", 0.2, "batch", 1, 0.011)};
  try {
    compare_results(base, next, {}, {}, make_info(), false, PairingRule{{"control.gain_scale"}});
    FAIL() << "two new jobs with gain_scale 0.2 paired silently";
  } catch (const AnalysisError& e) {
    EXPECT_STREQ(e.what(),
                 "--pair-by: new jobs b1 and b2 both have control.gain_scale=0.2; add what tells them apart to "
                 "--pair-by (they differ in seed)");
  }
  // With the seed among the pairing parameters: one pair, one new job unpaired.
  const ComparisonReport report =
      compare_results(base, next, {}, {}, make_info(), false, PairingRule{{"control.gain_scale", "seed"}});
  EXPECT_EQ(report.jobs_paired, 1);
  EXPECT_EQ(report.only_in_next, std::vector<std::string>{"b2"});
}

TEST(ComparisonPairing, RecordingKeysAndUnknownParametersAreRefused) {
  const std::vector<JobResult> jobs = {make_job("a1", 0.2, "online", 0, 0.010)};
  try {
    compare_results(jobs, jobs, {}, {}, make_info(), false, PairingRule{{"recording.series"}});
    FAIL();
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("recording keys only change what is recorded"), std::string::npos) << e.what();
  }
  try {
    compare_results(jobs, jobs, {}, {}, make_info(), false, PairingRule{{"control.gain_scal"}});
    FAIL();
  } catch (const AnalysisError& e) {
    EXPECT_STREQ(e.what(), "--pair-by control.gain_scal: no job has this parameter (did you mean 'control.gain_scale'?)");
  }
}

TEST(ComparisonPairing, ParametersAreReadAsConfigurationPaths) {
  const std::vector<JobResult> jobs = {make_job("a1", 0.2, "online", 0, 0.010)};
  // An element of the recording section is a recording key too; a key that only starts with
  // the section's name is not (it is an unknown parameter here).
  const auto refusal = [&](const std::string& param) -> std::string {
    try {
      compare_results(jobs, jobs, {}, {}, make_info(), false, PairingRule{{param}});
    } catch (const AnalysisError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(refusal("recording.series[0]").find("recording keys only change what is recorded"), std::string::npos);
  EXPECT_EQ(refusal("recordings").rfind("--pair-by recordings: no job has this parameter", 0), 0u) << refusal("recordings");
  EXPECT_EQ(refusal("control..gain_scale"), "--pair-by control..gain_scale: not a configuration path (empty key)");
  EXPECT_EQ(refusal("learning.mode"), "(accepted)");
}

}  // namespace
}  // namespace armfarm
