// Compare what users mean: jobs that differ only in what they record pair; --pair-by pairs by a
// chosen subset of parameters, refuses an ambiguous pairing naming what tells the jobs apart,
// refuses recording keys and unknown parameters.
#include "analysis/analysis_error.hpp"
#include "analysis/comparison.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

MetricInfoTable make_info() {
  MetricInfoTable info;
  for (const MetricInfoRecord& record : testing::make_test_metric_info()) info[record.name] = record;
  return info;
}

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
  EXPECT_EQ(report.metrics[1].verdict, Verdict::regressed);  // 0.02 -> 0.03, lower is better
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
