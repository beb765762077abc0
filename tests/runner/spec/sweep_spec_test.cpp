// Spec validation: a corpus of bad specs (tests/data/specs/bad), each giving one-line errors
// that name the file and the JSON path; includes merge in order. Below, folded in: the `search`
// block of a spec.
#include "runner/spec/sweep_spec.hpp"

#include "support/fake_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

namespace armfarm {
namespace {

const std::string kSpecs = std::string(ARMFARM_TEST_DATA_DIR) + "/specs/";

struct BadSpec {
  const char* file;
  const char* expected;  // the JSON path and message that must appear in one error line
};

const BadSpec kBadSpecs[] = {
    {"unknown_top_key", "sweeep: unknown key (did you mean 'sweep'?)"},
    {"missing_name", "name: missing"},
    {"unknown_config_key", "base.control.gain_scal: unknown key (did you mean 'gain_scale'?)"},
    {"wrong_type", "base.control.kp: expected an array, got \"high\""},
    {"wrong_type_element", "base.control.kp[1]: expected a number, got \"x\""},
    {"path_names_nothing", "sweep.grid[\"learning.lwpr.initD\"]: 'learning.lwpr.initD' names nothing in the job "
                           "configuration: no key 'initD' in 'learning.lwpr' (did you mean 'init_D'?)"},
    {"index_out_of_range", "sweep.grid[\"control.kp[5]\"]: 'control.kp[5]' names nothing in the job configuration: "
                           "index 5 is out of range"},
    {"axis_wrong_type", "sweep.grid[\"trajectory.kind\"][0]: expected a string, got 1"},
    {"out_of_range_value", "sweep.grid[\"control.gain_scale\"][1]: control.gain_scale: must be positive"},
    {"zip_lengths", "sweep.zip[0]: lists that vary together must have the same length"},
    {"random_bad_bounds", "sweep.random.params[\"learning.lwpr.init_D\"].loguniform: loguniform needs 0 < low"},
    {"random_unknown_distribution", "sweep.random.params[\"learning.lwpr.init_D\"].normal: unknown distribution"},
    {"repeat_zero", "sweep.repeat: expected a number of repeats"},
    {"not_json", "line 2, column 13: not valid JSON"},
    {"overlapping_axes", "overlaps 'control.kp'"},
    {"base_out_of_range", "base.simulation.samples: must be in [1, 1000000]"},
    {"include_bad", "bad_include_config.json: control.kq: unknown key (did you mean 'kd'?)"},
    {"unknown_sweep_key", "sweep.gird: unknown key (did you mean 'grid'?)"},
    {"integer_expected", "base.simulation.samples: expected an integer, got 2.5"},
};

// Loading and expanding is what `armfarm run` does before touching a database.
std::vector<std::string> collect_errors(const std::string& path) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  try {
    expand_sweep(load_sweep_spec(path, schema), schema);
  } catch (const SpecError& e) {
    return e.lines();
  }
  return {};
}

TEST(SweepSpec, EveryBadSpecIsRejectedWithFileAndJsonPath) {
  for (const BadSpec& bad : kBadSpecs) {
    const std::string path = kSpecs + "bad/" + bad.file + ".json";
    const std::vector<std::string> errors = collect_errors(path);
    ASSERT_FALSE(errors.empty()) << bad.file << " was accepted";
    bool found = false;
    for (const std::string& line : errors) {
      EXPECT_EQ(line.find('\n'), std::string::npos);
      EXPECT_NE(line.find(".json: "), std::string::npos) << line;
      if (line.find(bad.expected) != std::string::npos) found = true;
    }
    EXPECT_TRUE(found) << bad.file << ": expected \"" << bad.expected << "\" in:\n" << errors.front();
  }
}

TEST(SweepSpec, ErrorsNameTheSpecFile) {
  const auto errors = collect_errors(kSpecs + "bad/wrong_type.json");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind(kSpecs + "bad/wrong_type.json: ", 0), 0u) << errors[0];
  EXPECT_NE(collect_errors(kSpecs + "bad/no_such_file.json").at(0).find("no such file"), std::string::npos);
}

// A problem of a base value is located by its path, not by reading its line: a key written with
// ": " in it is not taken for the key its text begins with (the line's own text would have put
// the second problem at base.control.gain_scale, where the first one is).
TEST(SweepSpec, AValuesProblemIsLocatedByItsPathNotByItsText) {
  const std::string path = test_support::scratch_file("colon_key.json");
  std::ofstream(path) << "{\"name\": \"colon_key\",\n"
                         " \"base\": {\"control\": {\"gain_scale\": \"x\",\n"
                         "                      \"gain_scale: 2\": 1}}}\n";
  const std::vector<std::string> errors = collect_errors(path);
  std::filesystem::remove(path);
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0], path + ": base.control.gain_scale: expected a number, got \"x\" (line 2, column 37)");
  EXPECT_EQ(errors[1], path + ": base.control.gain_scale: 2: unknown key (did you mean 'gain_scale'?)");
}

TEST(SweepSpec, IncludesMergeInOrderAndBaseOverridesThem) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  const SweepSpec spec = load_sweep_spec(kSpecs + "fake_include.json", schema);
  EXPECT_EQ(spec.base["control"]["kp"], nlohmann::json({10.0, 20.0}));     // from the first include
  EXPECT_EQ(spec.base["control"]["gain_scale"], 3.0);                      // the second overrides the first
  EXPECT_EQ(spec.base["simulation"]["samples"], 50);
  EXPECT_EQ(spec.base["trajectory"]["kind"], "circle");
  EXPECT_EQ(spec.base["trajectory"]["period"], 1.5);                       // base
  EXPECT_EQ(spec.base["control"]["kd"], schema.defaults["control"]["kd"]);  // defaults elsewhere
  ASSERT_EQ(spec.grid.size(), 1u);
  EXPECT_TRUE(spec.base["control"]["gain_scale"].is_number_float());
}

TEST(SweepSpec, IntegersGivenForRealsAreNormalized) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  const SweepSpec spec =
      parse_sweep_spec(R"({"name": "n", "base": {"control": {"gain_scale": 2}}})", "inline.json", ".", schema);
  EXPECT_TRUE(spec.base["control"]["gain_scale"].is_number_float());
  EXPECT_EQ(spec.base["control"]["gain_scale"].get<double>(), 2.0);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/spec/spec_input_files_test.cpp:
// Spec files and includes go through the confined reader: /dev/zero, a FIFO, a directory or an
// oversized include is refused at once with the including spec and the path named, and a file
// that is not JSON is refused without its content in the message.

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class SpecInputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("spec_inputs");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // The spec's error lines joined by newlines ("" when it loads).
  std::string errors_of(const std::string& path) {
    try {
      load_sweep_spec(path, make_fake_job_config_schema());
    } catch (const SpecError& error) {
      std::string all;
      for (const std::string& line : error.lines()) all += line + "\n";
      return all;
    }
    return "";
  }

  std::string spec_including(const std::string& include) {
    return write("spec.json", "{\"name\": \"s\", \"include\": [\"" + include + "\"]}");
  }

  fs::path dir_;
};

TEST_F(SpecInputFiles, DevZeroIncludeIsRefusedAtOnce) {
  const std::string spec = spec_including("/dev/zero");
  const auto start = std::chrono::steady_clock::now();
  const std::string errors = errors_of(spec);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_EQ(errors, spec + ": include: /dev/zero: is a character device, not a regular file\n");
}

TEST_F(SpecInputFiles, FifoIncludeIsRefusedWithoutHanging) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.json").c_str(), 0600), 0);
  const std::string spec = spec_including("pipe.json");
  // Nobody writes to the FIFO: reading it would block until ctest's timeout.
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "pipe.json").string() + ": is a FIFO (named pipe), not a regular file\n");
}

TEST_F(SpecInputFiles, DirectoryIncludeAndDirectorySpecAreRefused) {
  fs::create_directories(dir_ / "folder");
  const std::string spec = spec_including("folder");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "folder").string() + ": is a directory, not a regular file\n");
  EXPECT_EQ(errors_of((dir_ / "folder").string()), (dir_ / "folder").string() + ": is a directory, not a regular file\n");
}

TEST_F(SpecInputFiles, OversizedIncludeIsRefusedWithItsSizeAndCap) {
  const std::string big = write("big.json", std::string((16u << 20) + 1, ' '));
  const std::string spec = spec_including("big.json");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + big + ": is 16777217 bytes, over the 16 MiB cap for JSON files\n");
}

TEST_F(SpecInputFiles, NonJsonIncludeIsNamedByLineNotQuoted) {
  write("passwd", "root:x:0:0:root:/root:/bin/bash\nsecret-user:x:1000:1000::/home/s:/bin/sh\n");
  const std::string errors = errors_of(spec_including("passwd"));
  EXPECT_NE(errors.find("passwd: line 1, column 1: not valid JSON"), std::string::npos) << errors;
  EXPECT_EQ(errors.find("root"), std::string::npos) << errors;
  EXPECT_EQ(errors.find("'r'"), std::string::npos) << errors;
}

TEST_F(SpecInputFiles, MissingIncludeNamesThePath) {
  const std::string spec = spec_including("nowhere.json");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "nowhere.json").string() + ": no such file\n");
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/spec/search_block_test.cpp:
// The `search` block of a sweep spec (sweeps/README.md, "Search"): what it reads, and the bad
// blocks `armfarm expand` refuses with the JSON path (an unknown key, an empty range, a metric
// with no direction, bounds outside the key table's range, ...).

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

std::vector<std::string> collect_search_errors(const std::string& text) {
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
      {"tpe_rule without tpe", R"({"method": "asha", "tpe_rule": "joint", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_rule: applies to TPE proposals only (method \"tpe\" or sampler \"tpe\")"},
      {"tpe_rule under random", R"({"method": "random", "tpe_rule": "per_axis", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_rule: applies to TPE proposals only"},
      {"unknown tpe_rule", R"({"method": "tpe", "tpe_rule": "per_axes", "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_rule: expected \"joint\" (the default) or \"per_axis\", not 'per_axes' (did you mean 'per_axis'?)"},
      {"tpe_rule not a string", R"({"method": "asha", "sampler": "tpe", "tpe_rule": true, "objective": {"metric": "heldout_test_nmse"},
          "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})",
       "sweep.search.tpe_rule: expected \"joint\" (the default) or \"per_axis\", not true"},
  };
  for (const BadBlock& b : bad) {
    const std::vector<std::string> errors = collect_search_errors(make_spec(b.block));
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
    return collect_search_errors(text.replace(text.find("METHOD"), 6, method));
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

TEST(SearchBlock, TpeRuleChoosesTheEstimatorRuleAndDefaultsToJoint) {
  const JobConfigSchema schema = make_experiment_config_schema();
  const auto parse = [&](const std::string& block) { return *parse_sweep_spec(make_spec(block), "spec.json", ".", schema).search; };
  const std::string tpe = R"({"method": "tpe", RULE"objective": {"metric": "heldout_test_nmse"},
      "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}})";
  const auto with = [&](const std::string& block, const std::string& rule) {
    std::string text = block;
    return parse(text.replace(text.find("RULE"), 4, rule));
  };
  const SpecSearch plain = with(tpe, "");
  EXPECT_TRUE(plain.settings.tpe.joint);  // the default
  EXPECT_FALSE(plain.tpe_rule_given);
  const SpecSearch per_axis = with(tpe, R"("tpe_rule": "per_axis", )");
  EXPECT_FALSE(per_axis.settings.tpe.joint);
  EXPECT_TRUE(per_axis.tpe_rule_given);
  const SpecSearch joint = with(tpe, R"("tpe_rule": "joint", )");
  EXPECT_TRUE(joint.settings.tpe.joint);
  EXPECT_TRUE(joint.tpe_rule_given);
  // The sampler of asha proposes with TPE too.
  std::string asha = kGood;
  ASSERT_NE(asha.find(R"("sampler": "tpe")"), std::string::npos);
  asha.insert(1, R"("tpe_rule": "per_axis", )");
  EXPECT_FALSE(parse(asha).settings.tpe.joint);
}

TEST(SearchBlock, ASearchDoesNotCombineWithGridAxes) {
  const std::string text = R"({"name": "s", "sweep": {"grid": {"control.gain_scale": [1, 2]},
      "search": {"method": "random", "objective": {"metric": "tracking_nmse"},
                 "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 4}}}})";
  const std::vector<std::string> errors = collect_search_errors(text);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("sweep.grid: does not combine with sweep.search"), std::string::npos) << errors[0];
}

}  // namespace
}  // namespace armfarm
