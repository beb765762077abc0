// `armfarm job CONFIG --db DB` (issue 12): a stored-model reference in learning.initial_model
// ({"job": KEY}, {"sweep": NAME, "params": {...}}) resolves from DB by the resolver sweep
// expansion uses, so the job gets the key `armfarm expand --db` gives it; the database is only
// read; a reference that is missing, ambiguous or has no database is one line naming the file
// and the JSON path, exit 2.
#include "results/results_store.hpp"
#include "support/command_line.hpp"
#include "support/text_file.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

struct CommandResult {
  int exit_code;
  std::string output;  ///< stdout
  std::string error;   ///< stderr
};


// Runs armfarm with `arguments`, stdout and stderr apart (stderr through `error_file`).
CommandResult run_command(const std::string& arguments, const std::string& error_file) {
  const test_support::CommandResult result =
      test_support::run_command_line("{ " + std::string(ARMFARM_BINARY) + " " + arguments + " 2>" + error_file + "; }");
  return {result.exit_code, result.output, test_support::read_text_file(error_file)};
}

// Two online jobs (gain scales 0.2 and 0.3, so two different models) on joints 2 and 4 that
// store their models.
constexpr const char* kTrainSpec = R"({
  "name": "jobdb_train", "description": "models for armfarm job --db",
  "base": {"active_joints": [2, 4], "trajectory": {"kind": "sine", "sine": {"duration": 2}},
           "learning": {"mode": "online", "store_model": true, "heldout": false}},
  "sweep": {"grid": {"control.gain_scale": [0.2, 0.3]}}
})";

// A frozen job on the same sine, starting from REFERENCE.
std::string make_frozen_config(const std::string& reference) {
  return R"({"active_joints": [2, 4], "control": {"gain_scale": 0.2}, "trajectory": {"kind": "sine", "sine": {"duration": 2}},
  "learning": {"mode": "frozen", "heldout": false,
               "initial_model": )" +
         reference + "}}\n";
}

class CmdJobStoredModel : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new fs::path(fs::temp_directory_path() / ("armfarm_job_db_" + std::to_string(::getpid())));
    fs::remove_all(*folder_);
    fs::create_directories(*folder_);
    std::ofstream(path("train.json")) << kTrainSpec;
    const CommandResult trained = run_command("run " + path("train.json") + " --db " + path("models.db") + " -j 1", path("train.err"));
    ASSERT_EQ(trained.exit_code, 0) << trained.output << trained.error;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*folder_);
    delete folder_;
  }
  static std::string path(const std::string& name) { return (*folder_ / name).string(); }
  static std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  static std::string job_key_of(double gain_scale) {
    const ResultsStore store = ResultsStore::open(path("models.db"), ResultsStore::Mode::read_only);
    for (const JobRecord& job : store.find_jobs("jobdb_train")) {
      if (job.params.value("control.gain_scale", -1.0) == gain_scale) return job.key;
    }
    return {};
  }
  static fs::path* folder_;
};

fs::path* CmdJobStoredModel::folder_ = nullptr;

// The job's results (not its timings) are the same: the same model drove the same job.
void expect_same_results(const nlohmann::json& a, const nlohmann::json& b) {
  for (const char* name : {"tracking_nmse", "id_nmse", "n_receptive_fields", "fb_abs_avg_first_segment"}) {
    EXPECT_EQ(a["metrics"][name], b["metrics"][name]) << name;
  }
}

TEST_F(CmdJobStoredModel, SweepReferenceResolvesFromTheDatabaseWithTheKeyExpansionGives) {
  const std::string config = write("by_sweep.json", make_frozen_config(R"({"sweep": "jobdb_train", "params": {"control.gain_scale": 0.2}})"));
  const std::string before = test_support::read_text_file(path("models.db"));
  const CommandResult job = run_command("job " + config + " --db " + path("models.db") + " --json", path("job.err"));
  ASSERT_EQ(job.exit_code, 0) << job.output << job.error;
  const nlohmann::json out = nlohmann::json::parse(job.output);
  EXPECT_EQ(out["status"], "done");
  // Read only: the database is byte for byte what it was.
  EXPECT_EQ(test_support::read_text_file(path("models.db")), before);

  // The same reference in a one-job spec: `armfarm expand --db` resolves it to the same key.
  nlohmann::json spec = {{"name", "jobdb_frozen"}, {"description", "x"}, {"base", nlohmann::json::parse(test_support::read_text_file(config))}};
  write("frozen_spec.json", spec.dump());
  const CommandResult expanded =
      run_command("expand " + path("frozen_spec.json") + " --db " + path("models.db") + " --json", path("expand.err"));
  ASSERT_EQ(expanded.exit_code, 0) << expanded.error;
  const nlohmann::json jobs = nlohmann::json::parse(expanded.output)["jobs"];
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(out["key"], jobs[0]["key"]);
  EXPECT_EQ(jobs[0]["config"]["inputs"]["learning.initial_model (stored)"]["job"], job_key_of(0.2));

  // The other job's model is another model: another key.
  const std::string other = write("other.json", make_frozen_config(R"({"sweep": "jobdb_train", "params": {"control.gain_scale": 0.3}})"));
  const CommandResult second = run_command("job " + other + " --db " + path("models.db") + " --json", path("job2.err"));
  ASSERT_EQ(second.exit_code, 0) << second.error;
  EXPECT_NE(nlohmann::json::parse(second.output)["key"], out["key"]);

  // A job key prefix names the same model as the sweep reference: the same key.
  const std::string by_job =
      write("by_job.json", make_frozen_config(R"({"job": ")" + job_key_of(0.2).substr(0, 10) + R"("})"));
  const CommandResult third = run_command("job " + by_job + " --db " + path("models.db") + " --json", path("job3.err"));
  ASSERT_EQ(third.exit_code, 0) << third.error;
  EXPECT_EQ(nlohmann::json::parse(third.output)["key"], out["key"]);
  expect_same_results(nlohmann::json::parse(third.output), out);

  // The configuration expansion recorded ("stored:<hash>" and its reference) runs with --db too.
  write("recorded.json", jobs[0]["config"].dump());
  const CommandResult recorded = run_command("job " + path("recorded.json") + " --db " + path("models.db") + " --json", path("rec.err"));
  ASSERT_EQ(recorded.exit_code, 0) << recorded.error;
  EXPECT_EQ(nlohmann::json::parse(recorded.output)["key"], out["key"]);
  expect_same_results(nlohmann::json::parse(recorded.output), out);
}

// One line on stderr naming the file and the JSON path, exit 2, nothing on stdout.
void expect_one_line_error(const CommandResult& result, const std::string& file, const std::string& detail) {
  EXPECT_EQ(result.exit_code, 2) << result.output << result.error;
  EXPECT_TRUE(result.output.empty()) << result.output;
  ASSERT_FALSE(result.error.empty());
  EXPECT_EQ(result.error.find('\n'), result.error.size() - 1) << result.error;
  EXPECT_NE(result.error.find(file + ": learning.initial_model: "), std::string::npos) << result.error;
  EXPECT_NE(result.error.find(detail), std::string::npos) << result.error;
}

TEST_F(CmdJobStoredModel, MissingOrAmbiguousReferenceIsOneLineNamingFileAndPath) {
  const std::string db = " --db " + path("models.db");
  const std::string missing = write("missing.json", make_frozen_config(R"({"job": "ffffffff"})"));
  expect_one_line_error(run_command("job " + missing + db, path("e1.err")), missing, "has no job with that key");
  const std::string ambiguous = write("ambiguous.json", make_frozen_config(R"({"sweep": "jobdb_train"})"));
  const CommandResult two = run_command("job " + ambiguous + db, path("e2.err"));
  expect_one_line_error(two, ambiguous, "2 jobs of sweep jobdb_train match these params");
  EXPECT_NE(two.error.find("(line 3, column "), std::string::npos) << two.error;  // where in the file
  const std::string no_sweep = write("no_sweep.json", make_frozen_config(R"({"sweep": "nosuch"})"));
  expect_one_line_error(run_command("job " + no_sweep + db, path("e3.err")), no_sweep, "has no sweep nosuch");
  // Without --db, and with a database that does not exist (which is not created).
  const std::string fine = write("fine.json", make_frozen_config(R"({"sweep": "jobdb_train", "params": {"control.gain_scale": 0.2}})"));
  expect_one_line_error(run_command("job " + fine, path("e4.err")), fine, "needs a results database");
  expect_one_line_error(run_command("job " + fine + " --db " + path("absent.db"), path("e5.err")), fine, "no such database file");
  EXPECT_FALSE(fs::exists(path("absent.db")));
}

}  // namespace
}  // namespace armfarm
