// Input files as `armfarm` sees them (issue 10): job keys cover the bytes of the model, its
// meshes and recorded trajectories but not where they sit; paths resolve relative to the file
// that wrote them, so a sweep runs from any directory; `run` says how many jobs are new because
// an input changed; numbers JSON cannot hold are refused with file, line/column and path.
// Real experiment jobs on the two-link planar arm, 0.1 s each.
#include "results/results_store.hpp"
#include "engine/io/input_file.hpp"
#include "runner/spec/input_files.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <set>
#include <sstream>

#include "support/command_line.hpp"
#include "support/text_file.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

// Runs armfarm in `directory` (the real experiment job), stdout and stderr together.
CommandResult run_armfarm(const fs::path& directory, const std::string& arguments) {
  const std::string command = "cd '" + directory.string() + "' && " + std::string(ARMFARM_BINARY) + " " +
                              arguments;
  return run_command_line(command);
}


void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A fresh scratch folder per test.
class InputFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = test_support::make_scratch_folder("inputs");
  }
  void TearDown() override { fs::remove_all(root_); }

  // tree/models/planar2.urdf and tree/specs/tiny.json, whose model path is relative to the spec.
  fs::path make_tree(const std::string& name) {
    const fs::path tree = root_ / name;
    write_file(tree / "models/planar2.urdf", test_support::read_text_file(fs::path(ARMFARM_SOURCE_DIR) / "models/planar2.urdf"));
    write_file(tree / "specs/tiny.json", R"({"name": "tiny",
 "base": {"model": "../models/planar2.urdf", "dt": 0.01,
          "control": {"mode": "feedback", "feed_forward": "none"}, "learning": {"mode": "none"},
          "trajectory": {"sine": {"duration": 0.1}}},
 "sweep": {"grid": {"control.gain_scale": [0.5, 1.0]}}}
)");
    return tree;
  }

  static void change_first_mass(const fs::path& model) {
    std::string text = test_support::read_text_file(model);
    const std::size_t at = text.find("<mass value=\"2.0\"/>");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 19, "<mass value=\"2.5\"/>");
    write_file(model, text);
  }

  // `armfarm expand --json` of a spec, run from `directory`.
  static nlohmann::json expand(const fs::path& directory, const std::string& spec) {
    const CommandResult result = run_armfarm(directory, "expand --json " + spec);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return nlohmann::json::parse(result.output);
  }

  static std::vector<std::string> keys_of(const nlohmann::json& expansion) {
    std::vector<std::string> keys;
    for (const auto& job : expansion["jobs"]) keys.push_back(job["key"].get<std::string>());
    return keys;
  }

  fs::path root_;
};

TEST_F(InputFilesTest, EditingAMassInACopiedModelChangesTheKeysAndMovingTheTreeDoesNot) {
  const fs::path a = make_tree("a");
  const fs::path b = make_tree("b");
  const nlohmann::json from_a = expand(root_, "a/specs/tiny.json");
  const nlohmann::json from_b = expand(b / "specs", "tiny.json");
  ASSERT_EQ(from_a["jobs"].size(), 2u);
  // Same bytes in another place: the same keys.
  EXPECT_EQ(keys_of(from_a), keys_of(from_b));
  // The stored configuration records the path as written, the resolved path and the hash.
  const nlohmann::json& model = from_b["jobs"][0]["config"]["inputs"]["model"];
  EXPECT_EQ(model["path"], "../models/planar2.urdf");
  EXPECT_EQ(fs::path(model["resolved"].get<std::string>()), fs::weakly_canonical(b / "models/planar2.urdf"));
  EXPECT_EQ(model["hash"].get<std::string>().size(), 32u);
  EXPECT_EQ(from_b["jobs"][0]["config"]["model"], "../models/planar2.urdf");

  change_first_mass(b / "models/planar2.urdf");
  const nlohmann::json edited = expand(root_, "b/specs/tiny.json");
  const std::vector<std::string> before = keys_of(from_a), after = keys_of(edited);
  ASSERT_EQ(after.size(), 2u);
  for (const std::string& key : after) EXPECT_EQ(std::count(before.begin(), before.end(), key), 0) << key;
  EXPECT_NE(edited["jobs"][0]["config"]["inputs"]["model"]["hash"], model["hash"]);
  // Only the hash changed: the configurations are otherwise equal.
  nlohmann::json x = from_b["jobs"][0]["config"], y = edited["jobs"][0]["config"];
  x.erase("inputs");
  y.erase("inputs");
  EXPECT_EQ(x, y);
}

TEST_F(InputFilesTest, MeshesOfADcgModelAreInputsToo) {
  const fs::path tree = root_ / "dcg";
  const fs::path data = fs::path(ARMFARM_TEST_DATA_DIR) / "models";
  write_file(tree / "arm/small.dcg", test_support::read_text_file(data / "small.dcg"));
  for (const char* mesh : {"obj/thesis_unit_box.obj", "obj/unit_cube_mixed.obj"}) {
    write_file(tree / "arm" / mesh, test_support::read_text_file(data / mesh));
  }
  write_file(tree / "spec.json", R"({"name": "dcg", "base": {"model": "arm/small.dcg"}})");
  const nlohmann::json first = expand(root_, "dcg/spec.json");
  const nlohmann::json& files = first["jobs"][0]["config"]["inputs"]["model"]["files"];
  ASSERT_EQ(files.size(), 3u) << files.dump();
  EXPECT_EQ(files[0]["file"], "small.dcg");
  EXPECT_EQ(files[1]["file"], "obj/thesis_unit_box.obj");
  EXPECT_EQ(files[2]["file"], "obj/unit_cube_mixed.obj");
  // A comment line added to one mesh changes the bytes, and so the key.
  write_file(tree / "arm/obj/unit_cube_mixed.obj", "# edited\n" + test_support::read_text_file(tree / "arm/obj/unit_cube_mixed.obj"));
  const nlohmann::json second = expand(root_, "dcg/spec.json");
  EXPECT_NE(keys_of(first), keys_of(second));
  EXPECT_EQ(second["jobs"][0]["config"]["inputs"]["model"]["files"][1], files[1]);
  EXPECT_NE(second["jobs"][0]["config"]["inputs"]["model"]["files"][2], files[2]);
}

TEST_F(InputFilesTest, SpecInAnotherDirectoryRunsFromAThirdOne) {
  make_tree("copied");
  fs::create_directories(root_ / "third");
  const CommandResult result = run_armfarm(root_ / "third", "run ../copied/specs/tiny.json --db out.db -j 1");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("2 done, 0 failed"), std::string::npos) << result.output;
  const ResultsStore store = ResultsStore::open((root_ / "third/out.db").string(), ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("tiny");
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].status, "done");
  EXPECT_EQ(fs::path(jobs[0].config["inputs"]["model"]["resolved"].get<std::string>()),
            fs::weakly_canonical(root_ / "copied/models/planar2.urdf"));
}

TEST_F(InputFilesTest, RunSaysHowManyJobsAreNewBecauseAnInputChanged) {
  const fs::path tree = make_tree("t");
  CommandResult first = run_armfarm(tree, "run specs/tiny.json --db r.db -j 1");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_EQ(first.output.find("because an input"), std::string::npos) << first.output;
  CommandResult again = run_armfarm(tree, "run specs/tiny.json --db r.db -j 1");
  EXPECT_NE(again.output.find("2 already done"), std::string::npos) << again.output;
  EXPECT_EQ(again.output.find("because an input"), std::string::npos) << again.output;
  change_first_mass(tree / "models/planar2.urdf");
  CommandResult changed = run_armfarm(tree, "run specs/tiny.json --db r.db -j 1");
  ASSERT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_NE(changed.output.find("2 jobs are new because an input file changed (model: 2)"), std::string::npos)
      << changed.output;
  EXPECT_NE(changed.output.find("2 done, 0 failed"), std::string::npos) << changed.output;
}

TEST_F(InputFilesTest, RecordedTrajectoryCsvIsAnInputRelativeToTheSpec) {
  const fs::path tree = make_tree("csv");
  std::string csv = "q1,q2\n";
  for (int i = 0; i < 50; ++i) csv += std::to_string(0.01 * i) + "," + std::to_string(-0.01 * i) + "\n";
  write_file(tree / "specs/data/q.csv", csv);
  write_file(tree / "specs/recorded.json", R"({"name": "recorded",
 "base": {"model": "../models/planar2.urdf", "control": {"mode": "feedback", "feed_forward": "none"},
          "learning": {"mode": "none"},
          "trajectory": {"kind": "recorded", "recorded": {"file": "data/q.csv", "task_space": false, "sample_rate": 100}}}})");
  const nlohmann::json first = expand(root_, "csv/specs/recorded.json");
  ASSERT_EQ(first["jobs"].size(), 1u);
  const nlohmann::json& entry = first["jobs"][0]["config"]["inputs"]["trajectory.recorded.file"];
  EXPECT_EQ(entry["path"], "data/q.csv");
  EXPECT_EQ(fs::path(entry["resolved"].get<std::string>()), fs::weakly_canonical(tree / "specs/data/q.csv"));
  write_file(tree / "specs/data/q.csv", csv + "0.5,-0.5\n");
  EXPECT_NE(keys_of(expand(root_, "csv/specs/recorded.json")), keys_of(first));
  // The job runs from the resolved path, from anywhere.
  const CommandResult run = run_armfarm("/", "run " + (tree / "specs/recorded.json").string() + " --db " +
                                                 (root_ / "r.db").string() + " -j 1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
}

TEST_F(InputFilesTest, IncludesResolveTheirPathsAgainstTheirOwnFolderAndAreInputs) {
  write_file(root_ / "common/planar2.urdf", test_support::read_text_file(fs::path(ARMFARM_SOURCE_DIR) / "models/planar2.urdf"));
  write_file(root_ / "common/arm.json", R"({"model": "planar2.urdf"})");
  write_file(root_ / "common/bad.json", R"({"model": "missing.urdf"})");
  write_file(root_ / "good.json", R"({"name": "i", "include": "common/arm.json"})");
  write_file(root_ / "bad.json", R"({"name": "i", "include": ["common/bad.json"], "base": {"dt": 5}})");
  fs::create_directories(root_ / "elsewhere");
  const nlohmann::json expansion = expand(root_ / "elsewhere", "../good.json");
  const nlohmann::json& inputs = expansion["jobs"][0]["config"]["inputs"];
  EXPECT_EQ(fs::path(inputs["model"]["resolved"].get<std::string>()), fs::weakly_canonical(root_ / "common/planar2.urdf"));
  EXPECT_EQ(inputs["include[0]"]["path"], "common/arm.json");
  EXPECT_EQ(inputs["include[0]"]["kind"], "include");
  // The include's bytes are in the key: even a whitespace-only edit gives new keys.
  write_file(root_ / "common/arm.json", R"({"model":  "planar2.urdf"})");
  EXPECT_NE(keys_of(expand(root_, "good.json")), keys_of(expansion));

  const CommandResult bad = run_armfarm(root_ / "elsewhere", "expand ../bad.json");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("common/bad.json: model: 'missing.urdf' resolves to " +
                            fs::weakly_canonical(root_ / "common").string() + "/missing.urdf: no such file"),
            std::string::npos)
      << bad.output;
  EXPECT_NE(bad.output.find("bad.json: base.dt: 5 s is outside the allowed range"), std::string::npos) << bad.output;
}

TEST_F(InputFilesTest, MissingModelDoesNotHideTheOtherErrors) {
  write_file(root_ / "spec.json", R"({"name": "x", "base": {"model": "nowhere/arm.urdf", "dt": -1, "control": {"gain_scale": -2}}})");
  const CommandResult result = run_armfarm(root_, "run spec.json --db r.db");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("spec.json: base.model: 'nowhere/arm.urdf' resolves to"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("spec.json: base.dt: -1 s is outside the allowed range"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("control.gain_scale: -2 is outside the allowed range"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("(checked with the default model, since the file cannot be read)"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(root_ / "r.db"));
}

TEST_F(InputFilesTest, JobResolvesRelativeToItsConfigFileAndKeepsTheSweepKey) {
  const fs::path tree = make_tree("job");
  write_file(tree / "one.json", R"({"model": "models/planar2.urdf", "learning": {"mode": "none"},
  "control": {"mode": "feedback", "feed_forward": "none"}, "trajectory": {"sine": {"duration": 0.05}}})");
  const CommandResult own = run_armfarm("/", "job " + (tree / "one.json").string() + " --json");
  ASSERT_EQ(own.exit_code, 0) << own.output;
  EXPECT_EQ(nlohmann::json::parse(own.output)["status"], "done");

  // A configuration from `expand --json`, saved elsewhere, runs from its recorded inputs with the sweep's key.
  const nlohmann::json expansion = expand(root_, "job/specs/tiny.json");
  write_file(root_ / "saved/config.json", expansion["jobs"][1]["config"].dump());
  const CommandResult stored = run_armfarm("/", "job " + (root_ / "saved/config.json").string() + " --json");
  ASSERT_EQ(stored.exit_code, 0) << stored.output;
  EXPECT_EQ(nlohmann::json::parse(stored.output)["key"], expansion["jobs"][1]["key"]);
}

TEST_F(InputFilesTest, NumbersJsonCannotHoldAreNamedWithFileLineAndPath) {
  write_file(root_ / "over.json", "{\"name\": \"x\",\n \"base\": {\"control\": {\"gain_scale\": 1e309}}}\n");
  CommandResult result = run_armfarm(root_, "run over.json --db r.db");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("over.json: line 2, column 37: base.control.gain_scale: the number 1e309 does not fit a double"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(root_ / "r.db"));

  write_file(root_ / "common/inc.json", "{\"dt\": -1e999}");
  write_file(root_ / "with_include.json", R"({"name": "x", "include": "common/inc.json"})");
  result = run_armfarm(root_, "expand with_include.json");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("common/inc.json: line 1, column 8: dt: the number -1e999 does not fit a double"), std::string::npos)
      << result.output;

  write_file(root_ / "axis.json", "{\"name\": \"x\",\n \"sweep\": {\"grid\": {\"control.kp\": [[1, 2], [3, 1E+400]]}}}");
  result = run_armfarm(root_, "expand axis.json");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("axis.json: line 2, column 48: sweep.grid[\"control.kp\"][1][1]: the number 1E+400"), std::string::npos)
      << result.output;

  write_file(root_ / "job.json", "{\"dt\": 0.001,\n  \"trajectory\": {\"sine\": {\"duration\": 1e309}}}");
  result = run_armfarm(root_, "job job.json");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("job.json: line 2, column 39: trajectory.sine.duration: the number 1e309"), std::string::npos)
      << result.output;

  // NaN and infinities spelled as strings where a number belongs.
  write_file(root_ / "nan.json", "{\"name\": \"x\",\n \"base\": {\"dt\": \"NaN\"},\n \"sweep\": {\"grid\": {\"control.gain_scale\": [1, \"-Infinity\"]}}}");
  result = run_armfarm(root_, "expand nan.json");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("nan.json: base.dt: expected a finite number, got \"NaN\""), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("(line 2, column 17)"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("nan.json: sweep.grid[\"control.gain_scale\"][1]: expected a finite number, got \"-Infinity\""),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("(line 3, column 47)"), std::string::npos) << result.output;
}

// record_input_files adds the resolved path to a problem only where the message lacks it, as the
// place that threw knows (not read off the text): a list_files that throws InputFileError names
// the file, any other exception does not, and a hash's error names the file it hashed.
TEST_F(InputFilesTest, AnInputsProblemNamesTheResolvedFileOnce) {
  write_file(root_ / "in/data.txt", "bytes");
  fs::create_directories(root_ / "in/sub");
  const std::string resolved = (root_ / "in/data.txt").lexically_normal().string();
  const auto problem_of = [&](std::function<std::vector<std::string>(const std::string&)> list_files) {
    InputFileField field;
    field.path = "file";
    field.list_files = std::move(list_files);
    nlohmann::json config = {{"file", "data.txt"}};
    InputFileReader reader;
    const std::vector<InputProblem> problems =
        record_input_files(config, {field}, [&](const std::string&) { return (root_ / "in").string(); }, reader);
    return problems.size() == 1 ? problems[0].field + ": " + problems[0].message : std::string("no single problem");
  };
  EXPECT_EQ(problem_of([](const std::string& path) -> std::vector<std::string> { throw InputFileError(path + ": bad model"); }),
            "file: 'data.txt' resolves to " + resolved + ": bad model");
  EXPECT_EQ(problem_of([](const std::string&) -> std::vector<std::string> { throw std::runtime_error("out of memory"); }),
            "file: 'data.txt' resolves to " + resolved + ": out of memory");
  const std::string folder = (root_ / "in/sub").string();
  EXPECT_EQ(problem_of([&](const std::string& path) { return std::vector<std::string>{path, folder}; }),
            "file: 'data.txt' resolves to " + resolved + ": " + folder + ": is a directory, not a regular file");
}

// A model that does not load: the loader's message names the resolved model file, once.
TEST_F(InputFilesTest, AModelThatDoesNotLoadIsNamedOnceInItsProblem) {
  const fs::path tree = make_tree("broken_model");
  write_file(tree / "models/planar2.urdf", "<robot name='x'><link name='a'>");
  const CommandResult result = run_armfarm(tree / "specs", "expand tiny.json");
  const std::string resolved = fs::weakly_canonical(tree / "models/planar2.urdf").lexically_normal().string();
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("tiny.json: base.model: '../models/planar2.urdf' resolves to " + resolved + ":"), std::string::npos)
      << result.output;
  EXPECT_EQ(result.output.find(resolved + ": " + resolved), std::string::npos) << result.output;
}

}  // namespace
}  // namespace armfarm
