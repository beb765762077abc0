// Regression checks: verdicts by direction and tolerance; exit codes 0, 1 and 2 of `compare`.
#include "analysis/analysis_error.hpp"
#include "analysis/comparison.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <fstream>

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

TEST(CompareCommand, TripledTorqueSaturationFailsTheCheck) {
  testing::TemporaryDirectory directory;
  auto make_jobs = [](double saturation) {
    testing::TestJob job;
    job.params = {{"control.gain_scale", 0.2}};
    job.metrics = {{0, "torque_saturation_fraction", 1, saturation, ""}};
    return std::vector<testing::TestJob>{job};
  };
  testing::write_test_sweep(directory.file("base.db"), "s", make_jobs(0.01));
  testing::write_test_sweep(directory.file("new.db"), "s", make_jobs(0.03));
  const auto result = testing::run_armfarm("compare " + directory.file("base.db") + " " + directory.file("new.db"));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("torque_saturation_fraction_j1"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("REGRESSED"), std::string::npos) << result.output;
}

TEST(CompareCommand, ExitCodesZeroOneTwo) {
  testing::TemporaryDirectory directory;
  auto make_jobs = [](double nmse) {
    testing::TestJob job;
    job.params = {{"control.gain_scale", 0.2}};
    job.metrics = {{0, "tracking_nmse", 1, nmse, ""},
                   {0, "sim_seconds_per_wall_second", std::nullopt, nmse * 1000, ""}};
    return std::vector<testing::TestJob>{job};
  };
  testing::write_test_sweep(directory.file("base.db"), "s", make_jobs(0.010));
  testing::write_test_sweep(directory.file("same.db"), "s", make_jobs(0.010));
  testing::write_test_sweep(directory.file("worse.db"), "s", make_jobs(0.020));
  const std::string base = directory.file("base.db");
  EXPECT_EQ(testing::run_armfarm("compare " + base + " " + directory.file("same.db")).exit_code, 0);
  const auto worse = testing::run_armfarm("compare " + base + " " + directory.file("worse.db"));
  EXPECT_EQ(worse.exit_code, 1) << worse.output;
  EXPECT_NE(worse.output.find("REGRESSED"), std::string::npos) << worse.output;
  EXPECT_EQ(testing::run_armfarm("compare " + base + " " + directory.file("worse.db") + " --rtol 2").exit_code, 0);
  EXPECT_EQ(testing::run_armfarm("compare " + base + " " + directory.file("absent.db")).exit_code, 2);
  EXPECT_EQ(testing::run_armfarm("compare " + base).exit_code, 2);
  {
    std::ofstream bad(directory.file("bad.json"));
    bad << "{\"metrics\": ";
  }
  const auto bad_tolerances = testing::run_armfarm("compare " + base + " " + base + " --tolerances " + directory.file("bad.json"));
  EXPECT_EQ(bad_tolerances.exit_code, 2);
  EXPECT_NE(bad_tolerances.output.find("bad.json: not valid JSON"), std::string::npos) << bad_tolerances.output;
  // A job missing from the new database is reported and fails the check.
  testing::write_test_sweep(directory.file("other.db"), "t", make_jobs(0.010));
  const auto missing = testing::run_armfarm("compare " + base + " " + directory.file("other.db") + " --format json");
  EXPECT_EQ(missing.exit_code, 1);
  const auto json = nlohmann::json::parse(missing.output);
  EXPECT_EQ(json["only_in_base"][0], "key_s_0");
  EXPECT_EQ(json["only_in_new"][0], "key_t_0");
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

TEST(CompareCommand, PairByPairsJobsOfDifferentConfigurations) {
  testing::TemporaryDirectory directory;
  auto make_jobs = [](const std::string& mode, double nmse) {
    std::vector<testing::TestJob> jobs;
    for (double gain : {0.2, 1.0}) {
      testing::TestJob job;
      job.params = {{"control.gain_scale", gain}, {"learning.mode", mode}};
      job.metrics = {{0, "tracking_nmse", 1, nmse * gain, ""}};
      jobs.push_back(job);
    }
    return jobs;
  };
  testing::write_test_sweep(directory.file("online.db"), "online", make_jobs("online", 0.01));
  testing::write_test_sweep(directory.file("batch.db"), "batch", make_jobs("batch", 0.008));
  const std::string both = directory.file("online.db") + " " + directory.file("batch.db");
  const auto whole = testing::run_armfarm("compare " + both);
  EXPECT_EQ(whole.exit_code, 1) << whole.output;  // nothing pairs: every base job is missing
  EXPECT_NE(whole.output.find("Compared 0 jobs"), std::string::npos) << whole.output;
  const auto paired = testing::run_armfarm("compare " + both + " --pair-by control.gain_scale --all");
  EXPECT_EQ(paired.exit_code, 0) << paired.output;
  EXPECT_NE(paired.output.find("Compared 2 jobs paired by control.gain_scale, 2 metrics: 0 regressed, 2 improved"),
            std::string::npos)
      << paired.output;
  const auto typo = testing::run_armfarm("compare " + both + " --pair-by control.gain");
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
  EXPECT_NE(typo.output.find("--pair-by control.gain: no job has this parameter"), std::string::npos) << typo.output;
}

}  // namespace
}  // namespace armfarm
