// Bounded expansion (issue 16): a sweep is counted before it is expanded and refused over the
// job limit at once, with its count; what a sweep keeps per job is compact.
#include "runner/execution/fake_job.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <gtest/gtest.h>

#include "support/command_line.hpp"
#include "support/scratch_file.hpp"

#include <cstdio>
#include <limits>
#include <string>

namespace armfarm {
namespace {

// {"name": "big", "sweep": {"grid": {"PATH": [0..n-1] / 100, ...}}} over the given paths.
std::string make_grid_spec(const std::vector<std::string>& paths, int values) {
  std::string grid;
  for (const std::string& path : paths) {
    std::string list;
    for (int i = 0; i < values; ++i) list += (i ? "," : "") + std::to_string(1 + i) + ".5";
    grid += std::string(grid.empty() ? "" : ", ") + "\"" + path + "\": [" + list + "]";
  }
  return R"({"name": "big", "sweep": {"grid": {)" + grid + "}}}";
}

SweepSpec parse(const std::string& text) {
  return parse_sweep_spec(text, "big.json", ".", make_fake_job_config_schema());
}

std::vector<std::string> refusal_of(const std::string& text, const ExpansionLimits& limits = {}) {
  try {
    expand_sweep(parse(text), make_fake_job_config_schema(), limits);
  } catch (const SpecError& error) {
    return error.lines();
  }
  return {};
}

TEST(BoundedExpansion, AMillionJobGridIsRefusedWithItsCount) {
  // Two axes of 1000 values: 10^6 jobs, which used to take 7.9 GB before anything was printed.
  const std::vector<std::string> lines = refusal_of(make_grid_spec({"control.gain_scale", "trajectory.period"}, 1000));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "big.json: sweep: expands to 1000000 jobs, over the limit of 100000 (--max-jobs N raises it)");
}

TEST(BoundedExpansion, TheLimitIsConfigurableAndInclusive) {
  const std::string text = make_grid_spec({"control.gain_scale", "trajectory.period"}, 3);  // 9 jobs
  ExpansionLimits limits;
  limits.max_jobs = 8;
  EXPECT_EQ(refusal_of(text, limits),
            std::vector<std::string>{"big.json: sweep: expands to 9 jobs, over the limit of 8 (--max-jobs N raises it)"});
  limits.max_jobs = 9;
  EXPECT_EQ(expand_sweep(parse(text), make_fake_job_config_schema(), limits).jobs.size(), 9u);
}

TEST(BoundedExpansion, CountIsTheProductOfEveryAxisAndSaturates) {
  const SweepSpec spec = parse(R"({"name": "n", "sweep": {
      "grid": {"control.gain_scale": [0.5, 1, 2]},
      "zip": [{"learning.lwpr.init_D": [10, 20, 40, 80], "learning.lwpr.init_alpha": [100, 200, 400, 800]}],
      "random": {"samples": 5, "params": {"trajectory.period": {"uniform": [1, 2]}}},
      "repeat": 2}})");
  EXPECT_EQ(calc_expansion_count(spec), 3u * 4u * 5u * 2u);
  EXPECT_EQ(calc_expansion_count(parse(R"({"name": "one"})")), 1u);
  // Seven axes of 1000 values: 10^21 configurations, more than a uint64 holds.
  const std::vector<std::string> seven = {"control.gain_scale", "trajectory.period", "trajectory.amplitude",
                                          "simulation.duration", "learning.lwpr.init_D", "learning.lwpr.init_alpha",
                                          "fake.sleep_ms"};
  const SweepSpec huge = parse(make_grid_spec(seven, 1000));
  EXPECT_EQ(calc_expansion_count(huge), std::numeric_limits<std::uint64_t>::max());
  const std::vector<std::string> lines = refusal_of(make_grid_spec(seven, 1000));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("expands to more than 1.8e19 jobs"), std::string::npos) << lines[0];
}

TEST(BoundedExpansion, JobsShareTheirBaseAndInputsAndRebuildTheSameConfiguration) {
  const ExpandedSweep sweep = expand_sweep(parse(make_grid_spec({"control.gain_scale", "trajectory.period"}, 4)),
                                           make_fake_job_config_schema());
  ASSERT_EQ(sweep.jobs.size(), 16u);
  for (const ExpandedJob& job : sweep.jobs) {
    EXPECT_EQ(job.base.get(), sweep.jobs.front().base.get());
    const nlohmann::json config = job.config();
    EXPECT_EQ(job.key, calc_job_key(config));
    EXPECT_EQ(config["control"]["gain_scale"], job.params["control.gain_scale"]);
    EXPECT_EQ(config["trajectory"]["period"], job.params["trajectory.period"]);
    EXPECT_EQ(config["trajectory"]["amplitude"], (*job.base)["trajectory"]["amplitude"]);
  }
}

TEST(BoundedExpansion, FromConfigKeepsAConfigurationAsItIs) {
  const nlohmann::json config = {{"seed", 7}, {"control", {{"gain_scale", 0.5}}}, {"inputs", {{"model", {{"hash", "ab"}}}}}};
  const ExpandedJob job = ExpandedJob::from_config(config);
  EXPECT_EQ(job.config(), config);
  EXPECT_EQ(job.key, calc_job_key(config));
  EXPECT_EQ(job.seed, 7);
  ASSERT_TRUE(job.inputs);
  EXPECT_FALSE(job.base->contains("inputs"));
}

TEST(BoundedExpansion, ExpandRefusesFromTheCommandLineWithExitTwo) {
  const std::string spec = test_support::scratch_file("bounded_expansion.json");
  {
    FILE* file = std::fopen(spec.c_str(), "w");
    ASSERT_NE(file, nullptr);
    std::fputs(make_grid_spec({"control.gain_scale", "trajectory.period"}, 1000).c_str(), file);
    std::fclose(file);
  }
  const auto refused = test_support::run_armfarm_with_fake_jobs("expand " + spec);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(refused.output, "armfarm: " + spec + ": sweep: expands to 1000000 jobs, over the limit of 100000 (--max-jobs N raises it)\n");
  const auto raised = test_support::run_armfarm_with_fake_jobs("expand " + spec + " --max-jobs 999999");
  EXPECT_EQ(raised.exit_code, 2) << raised.output;
  EXPECT_NE(raised.output.find("over the limit of 999999"), std::string::npos) << raised.output;
  std::remove(spec.c_str());
}

}  // namespace
}  // namespace armfarm
