// `armfarm run` as a process (armfarm_fakejobs: the fake job): killed with SIGKILL in the
// middle of a sweep it loses no finished job and resumes to the uninterrupted result; SIGINT
// stops it cleanly; bad specs exit 2 without creating a database; the other subcommands read the
// result.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include <sqlite3.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

CommandResult run_command(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_FAKE_JOBS_BINARY) + " " + arguments;
  return run_command_line(command);
}

// Starts `armfarm run` in its own process, output discarded; returns its pid.
pid_t start_run(const std::vector<std::string>& arguments) {
  const pid_t pid = fork();
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    std::vector<char*> argv = {const_cast<char*>(ARMFARM_FAKE_JOBS_BINARY), const_cast<char*>("run")};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(ARMFARM_FAKE_JOBS_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

int count_done(const std::string& db) {
  if (!fs::exists(db)) return 0;
  try {
    const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
    const auto counts = store.count_jobs_by_status("killme");
    return counts.count("done") ? counts.at("done") : 0;
  } catch (const StoreError&) {
    return 0;  // not created yet
  }
}

// key -> (status, attempts, metric values)
std::map<std::string, std::pair<std::string, std::vector<double>>> read_results(const std::string& db) {
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::map<std::string, std::pair<std::string, std::vector<double>>> results;
  for (const JobRecord& job : store.find_jobs("killme")) {
    std::vector<double> values;
    for (const MetricRecord& m : store.find_metrics(job.id)) values.push_back(m.value.value_or(std::nan("")));
    results[job.key] = {job.status, values};
  }
  return results;
}

class CmdRunTest : public test_support::ScratchFolderTest {
 protected:
  CmdRunTest() : ScratchFolderTest("cli") {}
  void SetUp() override {
    // 24 jobs of about 40 ms: long enough to be killed in the middle.
    std::ofstream(path("killme.json")) << R"({"name": "killme", "base": {"fake": {"sleep_ms": 40}},
        "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60]}, "repeat": 4}})";
  }
};

TEST_F(CmdRunTest, SigkillMidSweepLosesNoFinishedJobAndResumesToTheSameMetrics) {
  const std::string db = path("killed.db");
  const pid_t pid = start_run({path("killme.json"), "--db", db, "-j", "2"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (count_done(db) < 6 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the sweep ended before it could be killed";

  const auto before = read_results(db);
  int done_before = 0;
  for (const auto& [key, result] : before) done_before += result.first == "done";
  EXPECT_GE(done_before, 6);
  EXPECT_LT(done_before, 24);
  EXPECT_EQ(ResultsStore::open(db, ResultsStore::Mode::read_only).check_integrity(), "ok");

  const CommandResult resumed = run_command("run " + path("killme.json") + " --db " + db + " -j 2");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find(std::to_string(done_before) + " already done"), std::string::npos) << resumed.output;
  const auto after = read_results(db);
  for (const auto& [key, result] : before) {
    if (result.first == "done") {
      EXPECT_EQ(after.at(key), result) << key << " changed after resume";
    }
  }
  EXPECT_EQ(ResultsStore::open(db, ResultsStore::Mode::read_only).check_integrity(), "ok");

  const CommandResult clean = run_command("run " + path("killme.json") + " --db " + path("clean.db") + " -j 1");
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_EQ(after, read_results(path("clean.db")));
  EXPECT_EQ(after.size(), 24u);
}

TEST_F(CmdRunTest, SigintStopsCleanlyAndTheNextRunResumes) {
  const std::string db = path("int.db");
  const pid_t pid = start_run({path("killme.json"), "--db", db, "-j", "2"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (count_done(db) < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  {
    const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
    const auto counts = store.count_jobs_by_status("killme");
    EXPECT_EQ(counts.count("running"), 0u);  // interrupted jobs went back to pending
    EXPECT_GT(counts.at("pending"), 0);
    EXPECT_EQ(store.check_integrity(), "ok");
  }
  const CommandResult resumed = run_command("run " + path("killme.json") + " --db " + db);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(read_results(db).size(), 24u);
}

TEST_F(CmdRunTest, BadSpecExitsTwoWithoutCreatingTheDatabase) {
  const CommandResult result = run_command("run " + std::string(ARMFARM_TEST_DATA_DIR) +
                                           "/specs/bad/unknown_config_key.json --db " + path("never.db"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("base.control.gain_scal: unknown key (did you mean 'gain_scale'?)"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(path("never.db")));
}

TEST_F(CmdRunTest, ExpandJsonGivesKeysParamsAndConfigs) {
  const CommandResult result = run_command("expand --json " + path("killme.json"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  ASSERT_EQ(out["jobs"].size(), 24u);
  const auto& job = out["jobs"][5];
  EXPECT_EQ(job["key"].get<std::string>().size(), 32u);
  EXPECT_EQ(job["params"].size(), 2u);
  EXPECT_EQ(job["config"]["seed"], job["params"]["seed"]);
  EXPECT_EQ(job["config"]["fake"]["sleep_ms"], 40.0);
}

TEST_F(CmdRunTest, StatusTableAndExportReadTheResults) {
  std::ofstream(path("small.json")) << R"({"name": "small", "base": {"fake": {"sleep_ms": 0}},
      "sweep": {"zip": {"learning.lwpr.init_D": [10, 20], "fake.fail": [false, true]}}})";
  const std::string db = path("small.db");
  const CommandResult run = run_command("run " + path("small.json") + " --db " + db);
  EXPECT_EQ(run.exit_code, 1) << run.output;  // one job failed
  const CommandResult status = run_command("status " + db);
  EXPECT_EQ(status.exit_code, 1);
  EXPECT_NE(status.output.find("2 jobs, 1 done, 1 failed"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("fake job asked to fail"), std::string::npos) << status.output;
  const CommandResult table = run_command("table " + db + " --sweep small");
  EXPECT_EQ(table.exit_code, 0);
  EXPECT_NE(table.output.find("tracking_nmse_j2"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("0, 1 failed"), std::string::npos) << table.output;  // failed jobs counted, not averaged
  EXPECT_NE(table.output.find("learning.lwpr.init_D"), std::string::npos) << table.output;

  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const JobRecord job = store.find_jobs("small").at(0);
  const SeriesRecord pos = *store.find_series(job.id, "POS");
  const CommandResult csv = run_command("export " + db + " --job " + job.key.substr(0, 10) + " --series POS");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  EXPECT_EQ(csv.output.substr(0, csv.output.find('\n')), "t,q1,q2");
  const std::size_t lines = static_cast<std::size_t>(std::count(csv.output.begin(), csv.output.end(), '\n'));
  EXPECT_EQ(lines, static_cast<std::size_t>(pos.rows.rows()) + 1);
  // The second line is the first sample, printed exactly.
  const std::string first = csv.output.substr(csv.output.find('\n') + 1);
  EXPECT_EQ(std::stod(first.substr(first.find(',') + 1)), pos.rows(0, 1));
  EXPECT_EQ(run_command("export " + db + " --job " + job.key + " --series NOPE").exit_code, 2);
}

TEST_F(CmdRunTest, CommandsOnFilesThatAreNotResultsDatabasesExitTwo) {
  std::ofstream(path("junk.db")) << std::string(4096, 'j');
  const CommandResult result = run_command("status " + path("junk.db"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("not a readable SQLite database"), std::string::npos) << result.output;
  EXPECT_EQ(run_command("table " + path("missing.db")).exit_code, 2);
}

// `status --check` and `merge` on a damaged file: exit 2, one line per problem naming the file,
// and a merge leaves its output exactly as it was (here: not even created).
TEST_F(CmdRunTest, StatusCheckAndMergeRefuseADamagedDatabaseNamingIt) {
  std::ofstream(path("small.json")) << R"({"name": "small", "base": {"fake": {"sleep_ms": 0}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20]}}})";
  const std::string db = path("small.db");
  ASSERT_EQ(run_command("run " + path("small.json") + " --db " + db).exit_code, 0);
  const CommandResult sound = run_command("status --check " + db);
  EXPECT_EQ(sound.exit_code, 0) << sound.output;
  EXPECT_NE(sound.output.find("check passed"), std::string::npos) << sound.output;

  sqlite3* handle = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(handle, "DELETE FROM sweeps", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(handle);
  const CommandResult check = run_command("status --check " + db);
  EXPECT_EQ(check.exit_code, 2);
  EXPECT_EQ(check.output.rfind("armfarm: " + db + ": runs row 1: refers to a missing row of sweeps", 0), 0u)
      << check.output;
  // Issue 30, case 6: without --check, status (and table) exited 0 on this file; the readers'
  // check now refuses it, in one line naming the file and the row.
  for (const std::string& command : {"status " + db, "table " + db}) {
    const CommandResult plain = run_command(command);
    EXPECT_EQ(plain.exit_code, 2) << command;
    EXPECT_EQ(plain.output.rfind("armfarm: " + db + ": damaged armfarm database: runs row 1: refers to a missing row of sweeps", 0), 0u)
        << command << ": " << plain.output;
  }
  const std::string out = path("merged.db");
  const CommandResult merge = run_command("merge " + out + " " + db);
  EXPECT_EQ(merge.exit_code, 2);
  EXPECT_EQ(merge.output.rfind("armfarm: " + db + ": damaged armfarm database: ", 0), 0u) << merge.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace armfarm
