// `armfarm compare` through the command line: exit codes 0, 1 and 2, a tripled torque saturation
// fails the check, --pair-by pairs jobs of different configurations. The comparison itself:
// tests/analysis/comparison_test.cpp.
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace armfarm {
namespace {

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
