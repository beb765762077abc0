// The `search` block of a sweep spec (sweeps/README.md, "Search"): what it reads, and the bad
// blocks `armfarm expand` refuses with the JSON path (an unknown key, an empty range, a metric
// with no direction, bounds outside the key table's range, ...).
#include "runner/execution/job_executor.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"
#include "tests/support/command_line.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace armfarm {
namespace {

// A reaching task with checkpoints after 10, 50 and 200 reaches, and `search` as its sweep.
std::string make_spec(const std::string& search) {
  return R"({"name": "s", "base": {"trajectory": {"kind": "reaching"},
             "learning": {"heldout_checkpoints": [10, 50, 200]}},
             "sweep": {"search": )" + search + "}}";
}

const std::string kGood = R"({"method": "asha", "sampler": "tpe", "seed": 4, "slots": 3,
  "objective": {"metric": "heldout_test_nmse", "joint": "mean"},
  "space": {"learning.lwpr.init_D": {"log_uniform": [1, 1000]},
            "learning.lwpr.init_alpha": {"uniform": [10, 500]},
            "learning.lwpr.init_n_reg": {"integer": [1, 3]},
            "learning.lwpr.update_D": {"categorical": [false, true]}},
  "budget": {"cpu_seconds": 3600}})";

std::vector<std::string> collect_errors(const std::string& text) {
  const JobConfigSchema schema = make_experiment_config_schema();
  try {
    parse_sweep_spec(text, "spec.json", ".", schema);
  } catch (const SpecError& e) {
    return e.lines();
  }
  return {};
}

TEST(SearchBlock, AGoodBlockReadsItsMethodObjectiveRungsAndSpace) {
  const JobConfigSchema schema = make_experiment_config_schema();
  const SweepSpec spec = parse_sweep_spec(make_spec(kGood), "spec.json", ".", schema);
  ASSERT_TRUE(spec.search.has_value());
  const SpecSearch& search = *spec.search;
  EXPECT_EQ(search.settings.method, search::SearchMethod::asha);
  EXPECT_EQ(search.settings.sampler, search::SearchSampler::tpe);
  EXPECT_EQ(search.settings.seed, 4u);
  EXPECT_EQ(search.settings.eta, 3u);  // the default
  EXPECT_EQ(search.settings.slots, 3u);
  EXPECT_EQ(search.objective.metric, "heldout_test_nmse");
  EXPECT_TRUE(search.objective.lower_is_better);
  EXPECT_EQ(search.objective.joint, 0);
  EXPECT_EQ(search.objective.checkpoint, 200);
  EXPECT_EQ(search.rungs, (std::vector<std::int64_t>{10, 50, 200}));
  EXPECT_EQ(search.budget_unit, SpecSearch::BudgetUnit::cpu_seconds);
  ASSERT_EQ(search.settings.space.axes.size(), 4u);
  // nlohmann orders object keys: init_D, init_alpha, init_n_reg, update_D.
  EXPECT_EQ(search.settings.space.axes[0].kind, search::AxisKind::log_uniform);
  EXPECT_EQ(search.settings.space.axes[2].kind, search::AxisKind::integer);
  EXPECT_EQ(search.settings.space.axes[3].choice_count, 2u);
  // A step to rung 1 runs the checkpoints 10 and 50 and sets every axis.
  const nlohmann::json params = calc_search_step_params(search, {10.0, 20.0, 2.0, 1.0}, 1);
  EXPECT_EQ(params.at("learning.heldout_checkpoints"), nlohmann::json::parse("[10, 50]"));
  EXPECT_EQ(params.at("learning.lwpr.init_n_reg"), 2);
  EXPECT_EQ(params.at("learning.lwpr.update_D"), true);
  // Below the last rung the online reaching job learns exactly to the checkpoint: 50 reaches.
  EXPECT_EQ(search.length_path, "trajectory.reaching.reaches");
  EXPECT_EQ(params.at("trajectory.reaching.reaches"), 50);
  // The last rung is the base's job: its length is not set.
  EXPECT_FALSE(calc_search_step_params(search, {10.0, 20.0, 2.0, 1.0}, 2).contains("trajectory.reaching.reaches"));
}

TEST(SearchBlock, ShortAndLastRungStepsExpandTogetherWithTheKeysTheyHaveAlone) {
  // A sweep's job keys assume every step sets the same elements: the last rung sets the base's
  // own length. Expanded beside a short step, the last-rung job keeps the key it has alone.
  const JobConfigSchema schema = make_experiment_config_schema();
  const search::SearchPoint point = {10.0, 20.0, 2.0, 1.0};
  SweepSpec both = parse_sweep_spec(make_spec(kGood), "spec.json", ".", schema);
  const nlohmann::json base_reaches = both.base.at("trajectory").at("reaching").at("reaches");
  both.search->decided = std::vector<std::pair<search::SearchPoint, std::size_t>>{{point, 0}, {point, 2}};
  SweepSpec alone = both;
  alone.search->decided = std::vector<std::pair<search::SearchPoint, std::size_t>>{{point, 2}};
  const ExpandedSweep together = expand_sweep(std::move(both), schema);
  const ExpandedSweep single = expand_sweep(std::move(alone), schema);
  ASSERT_EQ(together.jobs.size(), 2u);
  EXPECT_EQ(together.jobs[0].config().at("trajectory").at("reaching").at("reaches"), 10);
  EXPECT_EQ(together.jobs[1].config().at("trajectory").at("reaching").at("reaches"), base_reaches);
  EXPECT_EQ(together.jobs[1].key, single.jobs.at(0).key);
}

TEST(SearchBlock, ShortRungsOfABatchJobTrainFewerEpochsAndRandomSearchesKeepTheBaseLength) {
  const JobConfigSchema schema = make_experiment_config_schema();
  const std::string batch = R"({"name": "b", "base": {"learning": {"mode": "batch", "epochs": 9, "heldout": true,
      "heldout_checkpoints": [1, 3, 9]}}, "sweep": {"search": {"method": "hyperband",
      "objective": {"metric": "heldout_test_nmse"}, "space": {"learning.lwpr.init_D": {"log_uniform": [1, 1000]}},
      "budget": {"jobs": 20}}}})";
  const SpecSearch search = *parse_sweep_spec(batch, "spec.json", ".", schema).search;
  EXPECT_EQ(search.length_path, "learning.epochs");
  EXPECT_EQ(calc_search_step_params(search, {5.0}, 0).at("learning.epochs"), 1);
  EXPECT_EQ(calc_search_step_params(search, {5.0}, 1).at("learning.epochs"), 3);
  EXPECT_FALSE(calc_search_step_params(search, {5.0}, 2).contains("learning.epochs"));
  // A one-rung method never cuts: its jobs are the base's.
  std::string tpe = batch;
  tpe.replace(tpe.find("hyperband"), 9, "tpe");
  EXPECT_TRUE(parse_sweep_spec(tpe, "spec.json", ".", schema).search->length_path.empty());
}

TEST(SearchBlock, ExpandListsTheStepsDecidedBeforeAnyResult) {
  const JobConfigSchema schema = make_experiment_config_schema();
  const ExpandedSweep sweep = expand_sweep(parse_sweep_spec(make_spec(kGood), "spec.json", ".", schema), schema);
  // ASHA starts a trial at rung 0 for each of the 3 slots; each a job with a normal key.
  ASSERT_EQ(sweep.jobs.size(), 3u);
  for (const ExpandedJob& job : sweep.jobs) {
    EXPECT_EQ(job.key.size(), 32u);
    EXPECT_EQ(job.config().at("learning").at("heldout_checkpoints"), nlohmann::json::parse("[10]"));
    EXPECT_EQ(job.config().at("trajectory").at("reaching").at("reaches"), 10);
    const double d = job.config().at("learning").at("lwpr").at("init_D").get<double>();
    EXPECT_GE(d, 1.0);
    EXPECT_LE(d, 1000.0);
  }
}

struct BadBlock {
  const char* name;
  std::string block;
  const char* expected;  // the JSON path and message that must appear in one line
};

TEST(SearchBlock, BadBlocksAreRefusedWithTheirJsonPath) {
  const std::vector<BadBlock> bad = {
      {"unknown key", R"({"method": "asha", "etta": 3, "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.etta: unknown key (did you mean 'eta'?)"},
      {"unknown space key", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.initD": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.initD\"]: 'learning.lwpr.initD' names nothing"},
      {"empty range", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"log_uniform": [5, 5]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.init_D\"].log_uniform: empty range [5, 5]"},
      {"reversed range", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_n_reg": {"integer": [3, 1]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.init_n_reg\"].integer: empty range [3, 1]"},
      {"no direction", R"({"method": "tpe", "objective": {"metric": "n_training_samples"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.objective.metric: 'n_training_samples' has no direction of better"},
      {"unknown metric", R"({"method": "tpe", "objective": {"metric": "heldout_tset_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.objective.metric: 'heldout_tset_nmse' is not a metric of the catalog (did you mean 'heldout_test_nmse'?)"},
      {"outside the key range", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.penalty": {"uniform": [0.5, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.penalty\"].uniform: [0.5, 2] leaves the key's range [0, 1]"},
      {"integer axis on a real key", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.penalty": {"integer": [0, 1]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.penalty\"].integer: draws integers"},
      {"checkpoint not listed", R"({"method": "asha", "objective": {"metric": "heldout_test_nmse", "checkpoint": 60},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.objective.checkpoint: expected \"last\" or one of learning.heldout_checkpoints [10,50,200]"},
      {"halving without checkpoints", R"({"method": "hyperband", "objective": {"metric": "tracking_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.objective.metric: successive halving needs an objective measured at learning checkpoints"},
      {"no budget", R"({"method": "random", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}})",
       "sweep.search.budget: missing"},
      {"unknown method", R"({"method": "ashaa", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.method: unknown method 'ashaa' (did you mean 'asha'?)"},
      {"one choice", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.update_D": {"categorical": [true]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.lwpr.update_D\"].categorical: expected a list of at least two values"},
      // An axis on a key every step sets (the rung's length, the checkpoints) would give it two values.
      {"reaches axis under asha", R"({"method": "asha", "objective": {"metric": "heldout_test_nmse"},
          "space": {"trajectory.reaching.reaches": {"integer": [200, 400]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"trajectory.reaching.reaches\"]: 'trajectory.reaching.reaches' is set by the search: a step to a rung runs trajectory.reaching.reaches up to that rung's checkpoint"},
      {"checkpoints axis", R"({"method": "tpe", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.heldout_checkpoints": {"categorical": [[10, 200], [50, 200]]}}, "budget": {"jobs": 9}})",
       "sweep.search.space[\"learning.heldout_checkpoints\"]: 'learning.heldout_checkpoints' is set by the search"},
      {"tpe_startup without tpe", R"({"method": "asha", "tpe_startup": 4, "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_startup: applies to TPE proposals only"},
      {"tpe_startup of one", R"({"method": "tpe", "tpe_startup": 1, "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_startup: expected an integer in [2, 1000000]"},
  };
  for (const BadBlock& b : bad) {
    const std::vector<std::string> errors = collect_errors(make_spec(b.block));
    ASSERT_FALSE(errors.empty()) << b.name << " was accepted";
    bool found = false;
    for (const std::string& line : errors) found = found || (line.find(b.expected) != std::string::npos && line.rfind("spec.json: ", 0) == 0);
    EXPECT_TRUE(found) << b.name << ": no line contains \"" << b.expected << "\"; got:\n" << errors.front();
  }
}

TEST(SearchBlock, AnEpochsAxisIsRefusedUnderSuccessiveHalvingOfABatchJobAndAllowedUnderTpe) {
  // learning.epochs is the length of a batch job's rung under asha, successive_halving and
  // hyperband; a one-rung method runs the base's length, so there it is an ordinary axis.
  const std::string batch = R"({"name": "b", "base": {"learning": {"mode": "batch", "epochs": 9, "heldout": true,
      "heldout_checkpoints": [1, 3, 9]}}, "sweep": {"search": {"method": "METHOD",
      "objective": {"metric": "heldout_test_nmse"}, "space": {"learning.epochs": {"integer": [9, 20]}},
      "budget": {"jobs": 20}}}})";
  const auto with = [&](const std::string& method) {
    std::string text = batch;
    return collect_errors(text.replace(text.find("METHOD"), 6, method));
  };
  for (const char* method : {"asha", "successive_halving", "hyperband"}) {
    const std::vector<std::string> errors = with(method);
    ASSERT_EQ(errors.size(), 1u) << method;
    EXPECT_NE(errors[0].find("spec.json: sweep.search.space[\"learning.epochs\"]: 'learning.epochs' is set by the search"),
              std::string::npos)
        << errors[0];
  }
  EXPECT_TRUE(with("tpe").empty());
  EXPECT_TRUE(with("random").empty());
}

TEST(SearchBlock, TpeStartupIsReadAndDefaultsToTheBudgetRule) {
  const JobConfigSchema schema = make_experiment_config_schema();
  std::string block = kGood;
  EXPECT_EQ(parse_sweep_spec(make_spec(block), "spec.json", ".", schema).search->tpe_startup, 0u);  // the rule
  block.insert(1, R"("tpe_startup": 5, )");
  EXPECT_EQ(parse_sweep_spec(make_spec(block), "spec.json", ".", schema).search->tpe_startup, 5u);
}

TEST(SearchBlock, ASearchDoesNotCombineWithGridAxes) {
  const std::string text = R"({"name": "s", "sweep": {"grid": {"control.gain_scale": [1, 2]},
      "search": {"method": "random", "objective": {"metric": "tracking_nmse"},
                 "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 4}}}})";
  const std::vector<std::string> errors = collect_errors(text);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("sweep.grid: does not combine with sweep.search"), std::string::npos) << errors[0];
}

TEST(SearchBlock, ExpandRefusesABadBlockWithExitTwoAndWritesNothing) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "armfarm_search_block_test";
  std::filesystem::create_directories(folder);
  const std::filesystem::path file = folder / "bad search.json";  // a space in the name
  std::ofstream(file) << make_spec(R"({"method": "tpe", "objective": {"metric": "n_training_samples"},
      "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})");
  const test_support::CommandResult result = test_support::run_armfarm("expand '" + file.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(file.string() + ": sweep.search.objective.metric: 'n_training_samples' has no direction"),
            std::string::npos)
      << result.output;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
