// `armfarm job`: runs one configuration, prints JSON metrics; bad files give one line and exit 2.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <sstream>

#include "support/command_line.hpp"
#include "results/results_store.hpp"
#include "support/text_file.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace {

CommandResult run_job(const std::string& arguments) {
  const std::string command = "cd " + std::string(ARMFARM_SOURCE_DIR) + " && " + ARMFARM_BINARY + " job " + arguments;
  return run_command_line(command);
}

std::string write_config(const std::string& name, const std::string& text) {
  const std::string path = armfarm::test_support::scratch_file("cmd_job_" + name + ".json");
  std::ofstream(path) << text;
  return path;
}

TEST(CmdJob, PrintsStatusMetricsAndOneObjectPerActiveJoint) {
  const std::string path = write_config(
      "ok", R"({"active_joints": [2, 4], "trajectory": {"sine": {"duration": 2.0}}, "control": {"gain_scale": 0.2}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_EQ(out["status"], "done");
  EXPECT_GT(out["metrics"]["n_receptive_fields"].get<double>(), 0.0);
  ASSERT_EQ(out["per_joint"].size(), 2u);
  EXPECT_EQ(out["per_joint"][0]["joint"], 2);
  EXPECT_EQ(out["per_joint"][1]["joint"], 4);
  EXPECT_TRUE(out["per_joint"][1].contains("ff_fb_ratio_avg"));
}

TEST(CmdJob, EveryNullHasAReasonBesideIt) {
  // Joint 7 holds still: its nMSE is undefined (null) and the job-level mean leaves it out.
  const std::string path = write_config("null", R"({"trajectory": {"sine": {"duration": 2.0,
      "amplitude": [0.3, 0.3, 0.3, 0.3, 0.3, 0.3, 0.0], "frequency": [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]}},
      "control": {"mode": "feedback", "feed_forward": "none"}, "learning": {"mode": "none"}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  int nulls = 0;
  const auto check = [&](const nlohmann::json& values, const nlohmann::json& reasons, const std::string& where) {
    for (const auto& [name, value] : values.items()) {
      if (!value.is_null()) continue;
      ++nulls;
      ASSERT_TRUE(reasons.is_object() && reasons.contains(name)) << where << " " << name << " is null without a reason";
      EXPECT_FALSE(reasons.at(name).get<std::string>().empty()) << where << " " << name;
    }
  };
  check(out["metrics"], out["reasons"], "metrics");
  for (const nlohmann::json& joint : out["per_joint"]) {
    check(joint, joint.value("reasons", nlohmann::json()), "joint " + joint["joint"].dump());
  }
  EXPECT_GE(nulls, 1);
  const nlohmann::json& seventh = out["per_joint"][6];
  ASSERT_EQ(seventh["joint"], 7);
  EXPECT_TRUE(seventh["tracking_nmse"].is_null());
  EXPECT_NE(seventh["reasons"]["tracking_nmse"].get<std::string>().find("nMSE floor"), std::string::npos) << seventh;
  // The mean is defined and says what it left out.
  EXPECT_TRUE(out["metrics"]["tracking_nmse"].is_number());
  EXPECT_NE(out["reasons"].value("tracking_nmse", "").find("7"), std::string::npos) << out["reasons"];
}

TEST(CmdJob, CheckpointsAreSpelledAsTheSweepViewSpellsThem) {
  const std::string path = write_config("checkpoints", R"({"trajectory": {"kind": "reaching",
      "reaching": {"reaches": 2, "points_per_reach": 50}}, "control": {"gain_scale": 0.2},
      "learning": {"mode": "online", "heldout_segments": 2, "heldout_checkpoints": [0, 2]}})");
  const CommandResult result = run_job(path + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_TRUE(out["metrics"].contains("heldout_test_nmse_c0")) << out["metrics"];
  EXPECT_TRUE(out["metrics"].contains("heldout_test_nmse_c2")) << out["metrics"];
  for (const auto& [name, value] : out["metrics"].items()) EXPECT_EQ(name.find('@'), std::string::npos) << name;
}

TEST(CmdJob, DivergedJobExitsOne) {
  const std::string path = write_config(
      "diverge", R"({"trajectory": {"sine": {"duration": 2.0}}, "control": {"mode": "feedback", "feed_forward": "none",
                    "gain_scale": 0.003}, "learning": {"mode": "none"}})");
  const CommandResult result = run_job(path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("status diverged"), std::string::npos) << result.output;
}

TEST(CmdJob, BadConfigurationIsOneLineNamingFileAndPath) {
  const std::string path = write_config("bad", R"({"control": {"gain_scal": 0.2}})");
  const CommandResult result = run_job(path);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find(path + ": control.gain_scal: unknown key"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

// The refused value is located by its path, not by reading the problem's line: a key written
// with ": " in it is not taken for the key its text begins with ("dt", at line 1, column 8).
TEST(CmdJob, AValuesProblemIsLocatedByItsPathNotByItsText) {
  const std::string located = write_config("located", "{\"dt\": \"fast\"}");
  const CommandResult typed = run_job(located);
  EXPECT_EQ(typed.exit_code, 2);
  EXPECT_EQ(typed.output, "armfarm: " + located + ": dt: expected a number, got \"fast\" (line 1, column 8)\n");
  const std::string colon = write_config("colon_key", "{\"dt\": 0.001, \"dt: 2\": 1}");
  const CommandResult unknown = run_job(colon);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.output, "armfarm: " + colon + ": dt: 2: unknown key\n");
}

TEST(CmdJob, NonsenseValuesAreRefusedBeforeTheJobStarts) {
  // Each of these used to run: dt 1e-300 ended done with NULL metrics, duration 1e300 overflowed
  // the tick count, integrator_accuracy 1e-300 hung.
  const std::pair<const char*, const char*> cases[] = {
      {R"({"dt": 1e-300})", "dt: 1e-300 s is outside the allowed range [0.0001, 0.1] s"},
      {R"({"trajectory": {"sine": {"duration": 1e300}}})", "trajectory.sine.duration: 1e+300 s is outside the allowed range"},
      {R"({"integrator_accuracy": 1e-300})", "integrator_accuracy: 1e-300 is outside the allowed range [1e-12, 0.1]"},
      {R"({"trajectory": {"sine": {"duration": 60000}}})", "trajectory.sine.duration: the job would take 6.0008e+06 control ticks"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string path = write_config("nonsense", text);
    const CommandResult result = run_job(path);
    EXPECT_EQ(result.exit_code, 2) << text << "\n" << result.output;
    EXPECT_NE(result.output.find(path + ": " + expected), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  }
}

TEST(CmdJob, WallTimeLimitStopsTheJob) {
  const std::string path = write_config("slow", R"({"trajectory": {"sine": {"duration": 600.0}}})");
  const auto start = std::chrono::steady_clock::now();
  const CommandResult result = run_job(path + " --timeout 0.3 --json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(result.exit_code, 1) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  EXPECT_EQ(out["status"], "timeout");
  EXPECT_EQ(out["message"], "stopped after the timeout of 0.3 s (--timeout)");
  EXPECT_LT(out["end_time"].get<double>(), 600.0);
  EXPECT_LT(seconds, 30.0);  // 600 simulated seconds take about 13 s of wall time uninterrupted
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Folded in from runner/cli/cmd_job_end_effector_test.cpp:
// The end effector of a job on a file with several leaf links: refused with both names and
// how to choose, accepted with `--ee` and with `end_effector.link` in the configuration (the
// same job key either way), and the choice is part of the key.

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace {

CommandResult run_job_in_cwd(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_BINARY) + " job " + arguments;
  return run_command_line(command);
}

class CmdJobEndEffector : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("armfarm_job_ee_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // A short feedback-only sine on two_leaves.urdf, plus `extra` keys.
  std::string write_config(const std::string& name, const std::string& extra) const {
    const std::string path = (folder_ / (name + ".json")).string();
    std::ofstream(path) << R"({"model": ")" << ARMFARM_TEST_DATA_DIR << R"(/models/two_leaves.urdf",
      "trajectory": {"sine": {"duration": 0.5}}, "control": {"mode": "feedback", "feed_forward": "none"},
      "learning": {"mode": "none"})" << extra << "}";
    return path;
  }

  std::filesystem::path folder_;
};

TEST_F(CmdJobEndEffector, SeveralLeavesAreRefusedListingThem) {
  const std::string path = write_config("plain", "");
  const CommandResult result = run_job_in_cwd(path);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(path + ": end_effector.link: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("2 leaf links ('tool0', 'camera_link'): set end_effector.link"),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("--ee LINK[:x,y,z]"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

TEST_F(CmdJobEndEffector, ChosenOnTheCommandLineOrInTheConfigurationRuns) {
  const CommandResult by_option = run_job_in_cwd(write_config("plain", "") + " --ee tool0 --json");
  ASSERT_EQ(by_option.exit_code, 0) << by_option.output;
  const nlohmann::json a = nlohmann::json::parse(by_option.output);
  EXPECT_EQ(a["status"], "done");

  const CommandResult by_config = run_job_in_cwd(write_config("config", R"(, "end_effector": {"link": "tool0"})") + " --json");
  ASSERT_EQ(by_config.exit_code, 0) << by_config.output;
  const nlohmann::json b = nlohmann::json::parse(by_config.output);
  EXPECT_EQ(b["status"], "done");
  EXPECT_EQ(a["key"], b["key"]);  // the same configuration either way

  const CommandResult camera = run_job_in_cwd(write_config("camera", "") + " --ee camera_link:0,0,0.01 --json");
  ASSERT_EQ(camera.exit_code, 0) << camera.output;
  EXPECT_NE(nlohmann::json::parse(camera.output)["key"], a["key"]);  // the choice is in the key
}

TEST_F(CmdJobEndEffector, BadChoicesAreOneLine) {
  const CommandResult unknown = run_job_in_cwd(write_config("unknown", R"(, "end_effector": {"link": "tool"})"));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("end_effector.link: "), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("no link 'tool' (leaf links: 'tool0', 'camera_link')"), std::string::npos) << unknown.output;

  const CommandResult offset_alone = run_job_in_cwd(write_config("offset", R"(, "end_effector": {"offset": [0, 0, 0.1]})"));
  EXPECT_EQ(offset_alone.exit_code, 2) << offset_alone.output;
  EXPECT_NE(offset_alone.output.find("end_effector.offset: an offset needs end_effector.link"), std::string::npos)
      << offset_alone.output;

  const CommandResult bad_text = run_job_in_cwd(write_config("text", "") + " --ee tool0:1,2");
  EXPECT_EQ(bad_text.exit_code, 2) << bad_text.output;
  EXPECT_NE(bad_text.output.find("--ee 'tool0:1,2': the offset needs three numbers"), std::string::npos) << bad_text.output;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
// Folded in from runner/cli/cmd_job_stored_model_test.cpp:
// `armfarm job CONFIG --db DB` (issue 12): a stored-model reference in learning.initial_model
// ({"job": KEY}, {"sweep": NAME, "params": {...}}) resolves from DB by the resolver sweep
// expansion uses, so the job gets the key `armfarm expand --db` gives it; the database is only
// read; a reference that is missing, ambiguous or has no database is one line naming the file
// and the JSON path, exit 2.

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
