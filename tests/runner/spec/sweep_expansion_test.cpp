// Expansion: counts (grid × zip × random × repeat), parameters, reproducible random samples,
// keys independent of how the spec is written; the fast job assembly against the plain one.
#include "support/fake_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_stages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <cstdio>
#include <limits>
#include <string>

namespace armfarm {
namespace {

ExpandedSweep expand_text(const std::string& text) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  return expand_sweep(parse_sweep_spec(text, "inline.json", ".", schema), schema);
}

std::vector<std::string> keys_of(const ExpandedSweep& sweep) {
  std::vector<std::string> keys;
  for (const auto& job : sweep.jobs) keys.push_back(job.key);
  return keys;
}

std::set<std::string> key_set_of(const ExpandedSweep& sweep) {
  const std::vector<std::string> keys = keys_of(sweep);
  return {keys.begin(), keys.end()};
}

TEST(SweepExpansion, CountIsTheProductOfGridZipAndRepeat) {
  const ExpandedSweep sweep = expand_text(R"({"name": "n", "sweep": {
      "grid": {"control.gain_scale": [0.5, 1, 2], "trajectory.kind": ["figure8", "circle"]},
      "zip": [{"learning.lwpr.init_D": [10, 20, 40, 80], "learning.lwpr.init_alpha": [100, 200, 400, 800]}],
      "repeat": [3, 5]}})");
  EXPECT_EQ(sweep.jobs.size(), 3u * 2u * 4u * 2u);
  EXPECT_EQ(key_set_of(sweep).size(), sweep.jobs.size());
  for (const ExpandedJob& job : sweep.jobs) {
    EXPECT_EQ(job.params.size(), 5u);
    // Zipped values stay together; params and config agree; key is the config's.
    EXPECT_DOUBLE_EQ(job.params["learning.lwpr.init_alpha"].get<double>(),
                     10.0 * job.params["learning.lwpr.init_D"].get<double>());
    EXPECT_EQ(job.config()["learning"]["lwpr"]["init_D"], job.params["learning.lwpr.init_D"]);
    EXPECT_EQ(job.config()["seed"], job.params["seed"]);
    EXPECT_EQ(job.seed, job.params["seed"].get<std::int64_t>());
    EXPECT_EQ(job.key, calc_job_key(job.config()));
  }
  // The first axis varies slowest, repeat fastest.
  EXPECT_EQ(sweep.jobs[0].params["seed"], 3);
  EXPECT_EQ(sweep.jobs[1].params["seed"], 5);
  EXPECT_EQ(sweep.jobs[0].params["control.gain_scale"], sweep.jobs[15].params["control.gain_scale"]);
}

TEST(SweepExpansion, NoSweepSectionIsOneJobAndRepeatCountStartsAtTheBaseSeed) {
  EXPECT_EQ(expand_text(R"({"name": "n"})").jobs.size(), 1u);
  const ExpandedSweep sweep = expand_text(R"({"name": "n", "base": {"seed": 10}, "sweep": {"repeat": 3}})");
  ASSERT_EQ(sweep.jobs.size(), 3u);
  EXPECT_EQ(sweep.jobs[2].seed, 12);
}

TEST(SweepExpansion, RandomSamplesAreReproducibleAndWithinBounds) {
  const std::string text = R"({"name": "n", "sweep": {"random": {"samples": 20, "seed": 7, "params": {
      "learning.lwpr.init_D": {"loguniform": [1, 100]},
      "control.gain_scale": {"uniform": [0.5, 2]},
      "trajectory.kind": {"choice": ["figure8", "circle"]}}}}})";
  const ExpandedSweep a = expand_text(text), b = expand_text(text);
  ASSERT_EQ(a.jobs.size(), 20u);
  EXPECT_EQ(keys_of(a), keys_of(b));
  std::set<std::string> kinds;
  double log_sum = 0.0;
  for (const ExpandedJob& job : a.jobs) {
    const double d = job.params["learning.lwpr.init_D"].get<double>();
    const double g = job.params["control.gain_scale"].get<double>();
    EXPECT_GE(d, 1.0);
    EXPECT_LE(d, 100.0);
    EXPECT_GE(g, 0.5);
    EXPECT_LE(g, 2.0);
    log_sum += std::log10(d);
    kinds.insert(job.params["trajectory.kind"].get<std::string>());
  }
  EXPECT_EQ(kinds.size(), 2u);
  EXPECT_NEAR(log_sum / 20.0, 1.0, 0.35);  // loguniform on [1, 100]: mean of log10 is 1, sd 0.58/sqrt(20)
  std::string other = text;
  other.replace(other.find("\"seed\": 7"), 9, "\"seed\": 8");
  EXPECT_NE(keys_of(expand_text(other)), keys_of(a));
}

TEST(SweepExpansion, KeysDoNotDependOnKeyOrderOrNumberFormatting) {
  const ExpandedSweep a = expand_text(R"({"name": "n", "base": {"control": {"kp": [100, 50]}},
      "sweep": {"grid": {"control.gain_scale": [1, 2.5], "learning.lwpr.init_D": [1e1, 25]}}})");
  const ExpandedSweep b = expand_text(R"({"sweep": {"grid": {"learning.lwpr.init_D": [25.0, 10], "control.gain_scale": [2.50, 1.0]}},
      "base": {"control": {"kp": [1e2, 50.0]}}, "name": "renamed"})");
  const std::set<std::string> ka = key_set_of(a), kb = key_set_of(b);
  EXPECT_EQ(ka.size(), 4u);
  EXPECT_EQ(ka, kb);
  EXPECT_EQ(a.spec_hash, b.spec_hash);
}

TEST(SweepExpansion, ChangingOneValueChangesOnlyTheJobsItTouches) {
  const ExpandedSweep a = expand_text(R"({"name": "n", "sweep": {"grid": {"control.gain_scale": [1, 2, 3]}, "repeat": 2}})");
  const ExpandedSweep b = expand_text(R"({"name": "n", "sweep": {"grid": {"control.gain_scale": [1, 2, 4]}, "repeat": 2}})");
  const std::set<std::string> ka = key_set_of(a);
  int shared = 0;
  for (const std::string& key : keys_of(b)) shared += static_cast<int>(ka.count(key));
  EXPECT_EQ(shared, 4);
  EXPECT_NE(a.spec_hash, b.spec_hash);
}

TEST(SweepExpansion, ArrayElementsCanBeSwept) {
  const ExpandedSweep sweep = expand_text(R"({"name": "n", "sweep": {"grid": {"control.kp[1]": [5, 6, 7]}}})");
  ASSERT_EQ(sweep.jobs.size(), 3u);
  EXPECT_EQ(sweep.jobs[2].config()["control"]["kp"], nlohmann::json({100.0, 7.0}));
}

// The speed-ups of the expansion (one tree edited in place, keys from cut-up texts) give what
// the plain assembly gives, a copy of the base per job hashed whole: every job, key, parameter,
// configuration and seed, and the spec hash, on shipped specs of every kind of axis (grid, zip,
// random, search, repeat, recorded input files, includes) and on the fake job's schema.
void expect_same_expansion(const ExpandedSweep& fast, const ExpandedSweep& plain, const std::string& name) {
  ASSERT_EQ(fast.jobs.size(), plain.jobs.size()) << name;
  EXPECT_EQ(fast.spec_hash, plain.spec_hash) << name;
  for (std::size_t i = 0; i < fast.jobs.size(); ++i) {
    EXPECT_EQ(fast.jobs[i].key, plain.jobs[i].key) << name << " job " << i;
    EXPECT_EQ(fast.jobs[i].params, plain.jobs[i].params) << name << " job " << i;
    EXPECT_EQ(fast.jobs[i].seed, plain.jobs[i].seed) << name << " job " << i;
    EXPECT_EQ(fast.jobs[i].config(), plain.jobs[i].config()) << name << " job " << i;
    EXPECT_EQ(plain.jobs[i].key, calc_job_key(plain.jobs[i].config())) << name << " job " << i;
  }
}

TEST(SweepExpansion, FastAssemblyGivesWhatThePlainOneGivesOnShippedSpecs) {
  const JobConfigSchema schema = make_experiment_config_schema();
  for (const char* name : {"quickstart.json", "learners.json", "thesis/fig6_12_13_recorded.json", "thesis/table6_4_sine.json",
                           "thesis/realtime_dof.json", "thesis/interference_two_task.json", "search/reaching_asha.json",
                           "search/fig6_1_kernel_width_tpe.json"}) {
    const std::string path = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/" + name;
    // A staged spec: its first stage (the others start from its stored models).
    const ExpandedSweep fast = expand_sweep(load_sweep_stages(path, schema).front(), schema, {}, JobAssemblyMethod::fast);
    const ExpandedSweep plain = expand_sweep(load_sweep_stages(path, schema).front(), schema, {}, JobAssemblyMethod::plain);
    EXPECT_GT(fast.jobs.size(), 0u) << name;
    expect_same_expansion(fast, plain, name);
  }
}

TEST(SweepExpansion, FastAssemblyGivesWhatThePlainOneGivesOnEveryKindOfAxis) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  const std::string text = R"({"name": "n", "sweep": {
      "grid": {"control.gain_scale": [0.5, 1, 2], "control.kp[1]": [1, 2]},
      "zip": [{"learning.lwpr.init_D": [10, 20], "trajectory.kind": ["figure8", "circle"]}],
      "random": {"samples": 3, "seed": 1, "params": {"learning.lwpr.init_alpha": {"loguniform": [1, 100]}}},
      "repeat": [3, 5]}})";
  const ExpandedSweep fast = expand_sweep(parse_sweep_spec(text, "inline.json", ".", schema), schema, {}, JobAssemblyMethod::fast);
  const ExpandedSweep plain = expand_sweep(parse_sweep_spec(text, "inline.json", ".", schema), schema, {}, JobAssemblyMethod::plain);
  EXPECT_EQ(fast.jobs.size(), 3u * 2u * 2u * 3u * 2u);
  expect_same_expansion(fast, plain, "inline");
  // And both refuse the same bad values with the same lines.
  const std::string bad = R"({"name": "n", "sweep": {"grid": {"control.gain_scale": [1, -1, 2], "control.kp[0]": [1, -2]}}})";
  std::string fast_error, plain_error;
  try {
    expand_sweep(parse_sweep_spec(bad, "inline.json", ".", schema), schema, {}, JobAssemblyMethod::fast);
  } catch (const SpecError& error) {
    fast_error = error.what();
  }
  try {
    expand_sweep(parse_sweep_spec(bad, "inline.json", ".", schema), schema, {}, JobAssemblyMethod::plain);
  } catch (const SpecError& error) {
    plain_error = error.what();
  }
  EXPECT_NE(fast_error.find("control.gain_scale"), std::string::npos) << fast_error;
  EXPECT_EQ(fast_error, plain_error);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/spec/bounded_expansion_test.cpp:
// Bounded expansion (issue 16): a sweep is counted before it is expanded and refused over the
// job limit at once, with its count; what a sweep keeps per job is compact.

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

}  // namespace
}  // namespace armfarm
