// `armfarm run` as a process (armfarm_fakejobs: the fake job): killed with SIGKILL in the
// middle of a sweep it loses no finished job and resumes to the uninterrupted result; SIGINT
// stops it cleanly; bad specs exit 2 without creating a database; the other subcommands read the
// result. Below, folded in: its progress output and full-disk truth, and sweeps over an arm with
// two end effectors.
#include "results/results_store.hpp"
#include "support/armfarm_process.hpp"
#include "support/command_line.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <signal.h>
#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

CommandResult run_command(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_FAKE_JOBS_BINARY) + " " + arguments;
  return run_command_line(command);
}

// Starts `armfarm run` (fake jobs) in its own process, output discarded.
test_support::ArmfarmProcess start_run(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), "run");
  return test_support::start_armfarm(arguments, "/dev/null");
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
  const test_support::ArmfarmProcess run = start_run({path("killme.json"), "--db", db, "-j", "2"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (count_done(db) < 6 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(run.pid, SIGKILL);
  ASSERT_EQ(test_support::wait_armfarm(run), 128 + SIGKILL) << "the sweep ended before it could be killed";

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
  const test_support::ArmfarmProcess run = start_run({path("killme.json"), "--db", db, "-j", "2"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (count_done(db) < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(run.pid, SIGINT);
  EXPECT_EQ(test_support::wait_armfarm(run), 1);
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

// ------------------------------------------------------------------------------------------------
// Folded in from runner/cli/cmd_run_progress_test.cpp:
// `armfarm run` as a user reads it (fake jobs): heartbeat lines with an ETA in a log, --quiet,
// the closing summary with the main metric, `armfarm --version`; and truthful progress under a
// full disk: no job printed `done` that the database does not hold, the run stops saying how
// many finished jobs were lost, and the next run reruns exactly the jobs that are not saved.

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;


// The short keys of the jobs a run's output printed as done.
std::set<std::string> find_printed_done(const std::string& output) {
  std::set<std::string> keys;
  const std::regex done_line(R"(\] done +([0-9a-f]{8}) )");
  for (std::sregex_iterator it(output.begin(), output.end(), done_line), end; it != end; ++it) keys.insert((*it)[1]);
  return keys;
}

std::set<std::string> find_stored(const std::string& db, const std::string& sweep, bool done) {
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::set<std::string> keys;
  for (const JobRecord& job : store.find_jobs(sweep)) {
    if ((job.status == "done") == done) keys.insert(job.key.substr(0, 8));
  }
  return keys;
}

class CmdRunProgressTest : public test_support::ScratchFolderTest {
 protected:
  CmdRunProgressTest() : ScratchFolderTest("progress_cli") {}
};

TEST_F(CmdRunProgressTest, ALogGetsHeartbeatLinesWithAnEtaAndTheSummaryNamesTheMainMetric) {
  // 12 jobs of 40 ms on 2 threads: about 0.25 s, heartbeats every 30 ms.
  std::ofstream(path("p.json")) << R"({"name": "p", "base": {"fake": {"sleep_ms": 40}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60]}, "repeat": 2}})";
  const CommandResult result = run_command("run " + path("p.json") + " --db " + path("p.db") + " -j 2 --heartbeat 0.03");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::regex heartbeat(R"(progress: (\d+)/12 done, 0 failed, (\d) running, elapsed [0-9.]+ s, ETA ([0-9.]+) s(; running( [0-9a-f]{8})+)?\n)");
  int with_eta = 0;
  for (std::sregex_iterator it(result.output.begin(), result.output.end(), heartbeat), end; it != end; ++it) ++with_eta;
  EXPECT_GE(with_eta, 2) << result.output;
  EXPECT_EQ(find_printed_done(result.output).size(), 12u) << result.output;
  EXPECT_NE(result.output.find("sweep p: 12 done, 0 failed, 0 diverged, 0 timed out, 0 already done (skipped); wall time "),
            std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("sweep p: main metric same_run_test_nmse (lower is better, 12 jobs): best "),
            std::string::npos)
      << result.output;

  const CommandResult quiet = run_command("run " + path("p.json") + " --db " + path("q.db") + " -j 2 --quiet --heartbeat 0.01");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("progress:"), std::string::npos) << quiet.output;
  EXPECT_EQ(quiet.output.find("] done"), std::string::npos) << quiet.output;
  EXPECT_NE(quiet.output.find("sweep p: 12 done"), std::string::npos) << quiet.output;
}

TEST_F(CmdRunProgressTest, VersionExitsZero) {
  const CommandResult result = run_command("--version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.rfind("armfarm ", 0), 0u) << result.output;
  EXPECT_EQ(run_command("version").exit_code, 0);
}

TEST_F(CmdRunProgressTest, AFullDiskPrintsNoDoneThatWasNotCommittedAndTheNextRunRerunsTheUnsavedJobs) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs; not root, so the disk-full case is not tested";
  const std::string disk = path("disk");
  fs::create_directories(disk);
  // 384 KiB: the sweep's registration fits, a few jobs' series (2000 noisy samples) do, 30 do not.
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=384k") != 0) {
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "); the disk-full case is not tested";
  }
  struct Unmount {
    std::string where;
    ~Unmount() { umount2(where.c_str(), MNT_DETACH); }
  } unmount{disk};
  std::ofstream(path("full.json")) << R"({"name": "full", "base": {"fake": {"sleep_ms": 5}, "simulation": {"samples": 2000}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60, 70, 80, 90, 100]}, "repeat": 3}})";
  const std::string db = disk + "/full.db";
  const CommandResult full = run_command("run " + path("full.json") + " --db " + db + " -j 2 --heartbeat 0");
  EXPECT_EQ(full.exit_code, 3) << full.output;  // results lost: not the "some jobs failed" 1
  const std::smatch lost = [&] {
    std::smatch match;
    std::regex_search(full.output, match, std::regex(R"(writing results failed \(.*full.*\); stopped: (\d+) finished jobs were not saved, (\d+) saved)"));
    return match;
  }();
  ASSERT_FALSE(lost.empty()) << full.output;
  const std::set<std::string> printed = find_printed_done(full.output);
  const std::set<std::string> stored = find_stored(db, "full", true);
  EXPECT_EQ(printed, stored) << full.output;
  EXPECT_LT(stored.size(), 30u) << "the disk did not fill";
  EXPECT_EQ(std::stoul(lost[2]), stored.size());
  EXPECT_NE(full.output.find("sweep full: " + std::to_string(stored.size()) + " done,"), std::string::npos) << full.output;
  const std::set<std::string> not_done = find_stored(db, "full", false);
  EXPECT_EQ(not_done.size(), 30u - stored.size());

  // Room again: the next run skips exactly the saved jobs and runs exactly the others.
  ASSERT_EQ(mount("tmpfs", disk.c_str(), "tmpfs", MS_REMOUNT, "size=64m"), 0) << std::strerror(errno);
  // The stopped run's claims could not be released on the full disk: a short lease lets the next
  // run take them over at once instead of after the default minute.
  ASSERT_EQ(run_command("lease " + db + " 0.5").exit_code, 0);
  const CommandResult resumed = run_command("run " + path("full.json") + " --db " + db + " -j 2 --heartbeat 0");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find(std::to_string(stored.size()) + " already done (skipped)"), std::string::npos)
      << resumed.output;
  EXPECT_EQ(find_printed_done(resumed.output), not_done) << resumed.output;
  EXPECT_EQ(find_stored(db, "full", true).size(), 30u);
  EXPECT_EQ(ResultsStore::open(db, ResultsStore::Mode::read_only).check_integrity(), "ok");
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/cli/cmd_run_end_effector_test.cpp:
// Sweeps over an arm with two leaf frames (tests/data/arms/kuka_iiwa14.urdf: the flange
// 'iiwa_link_ee' and a tool point 'tool_tcp'): `armfarm run` sweeps it with end_effector.link in
// the spec's base and as a grid axis (sharded too: the job-cost estimate makes each job's arm as
// the executor does), `slurm` writes its scripts, and a missing or unknown choice is refused at
// expansion by run, expand and slurm alike, in one line naming the spec, the leaves and the key,
// before any database is written.

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

class CmdRunEndEffector : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = armfarm::test_support::make_scratch_folder("run_ee"); }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // A sweep of short feedback-only sine jobs on the two-leaf arm; `base` and `sweep` are JSON
  // members added to the spec's base and its sweep block. pd_substeps 10: the arm has no rotor
  // inertia, and its wrist needs a finer PD period than 10 ms (issue 22).
  std::string write_spec(const std::string& name, const std::string& base, const std::string& sweep) const {
    const std::string path = (folder_ / (name + ".json")).string();
    std::ofstream(path) << R"({"name": ")" << name << R"(", "base": {"model": ")" << ARMFARM_TEST_DATA_DIR
                        << R"(/arms/kuka_iiwa14.urdf", "pd_substeps": 10,
        "trajectory": {"sine": {"duration": 0.5}}, "control": {"mode": "feedback", "feed_forward": "none"},
        "learning": {"mode": "none"})" << base << R"(}, "sweep": {)" << sweep << "}}";
    return path;
  }
  std::string db(const std::string& name) const { return (folder_ / (name + ".db")).string(); }

  std::filesystem::path folder_;
};

int count_lines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST_F(CmdRunEndEffector, ChoiceInTheBaseRuns) {
  const std::string spec = write_spec("in_base", R"(, "end_effector": {"link": "tool_tcp"})",
                                      R"("grid": {"control.gain_scale": [0.2, 1.0]})");
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("in_base") + " -j 2 --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("sweep in_base: 2 done, 0 failed, 0 diverged"), std::string::npos) << result.output;
}

TEST_F(CmdRunEndEffector, ChoiceAsAGridAxisRunsOneJobPerLink) {
  const std::string spec = write_spec("on_axis", "", R"("grid": {"end_effector.link": ["tool_tcp", "iiwa_link_ee"]})");
  const CommandResult expanded = run_armfarm("expand " + spec);
  ASSERT_EQ(expanded.exit_code, 0) << expanded.output;
  EXPECT_NE(expanded.output.find("end_effector.link=\"tool_tcp\""), std::string::npos) << expanded.output;
  EXPECT_NE(expanded.output.find("end_effector.link=\"iiwa_link_ee\""), std::string::npos) << expanded.output;
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("on_axis") + " -j 2 --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("sweep on_axis: 2 done, 0 failed, 0 diverged"), std::string::npos) << result.output;
}

TEST_F(CmdRunEndEffector, ShardedRunAndSlurmScriptsCostTheJobsOnTheChosenArm) {
  const std::string spec = write_spec("sharded", R"(, "end_effector": {"link": "iiwa_link_ee"})",
                                      R"("grid": {"control.gain_scale": [0.2, 0.5, 1.0]})");
  // What each array task of `armfarm slurm` runs: a shard, dealt by the jobs' estimated costs.
  const CommandResult shard = run_armfarm("run " + spec + " --shard 1/2 --db " + db("shard1") + " -j 2 --quiet");
  EXPECT_EQ(shard.exit_code, 0) << shard.output;
  EXPECT_NE(shard.output.find(" done, 0 failed, 0 diverged"), std::string::npos) << shard.output;
  EXPECT_NE(shard.output.find("of 3 jobs in this shard"), std::string::npos) << shard.output;
  const CommandResult slurm = run_armfarm("slurm " + spec + " --db " + db("cluster") + " --tasks 2");
  EXPECT_EQ(slurm.exit_code, 0) << slurm.output;
  EXPECT_TRUE(std::filesystem::exists(db("cluster") + ".array.sbatch")) << slurm.output;
}

TEST_F(CmdRunEndEffector, MissingChoiceIsRefusedAtExpansionNamingTheSpecTheLeavesAndTheKey) {
  const std::string spec = write_spec("no_choice", "", R"("grid": {"control.gain_scale": [0.2, 1.0]})");
  for (const std::string& command : {"run " + spec + " --db " + db("no_choice"), "expand " + spec,
                                     "slurm " + spec + " --db " + db("no_choice") + " --tasks 2"}) {
    SCOPED_TRACE(command);
    const CommandResult result = run_armfarm(command);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_EQ(result.output.rfind("armfarm: " + spec + ": base.end_effector.link: ", 0), 0u) << result.output;
    EXPECT_NE(result.output.find("kuka_iiwa14.urdf: 2 leaf links ('iiwa_link_ee', 'tool_tcp'): set end_effector.link"),
              std::string::npos)
        << result.output;
    EXPECT_EQ(count_lines(result.output), 1) << result.output;
  }
  EXPECT_FALSE(std::filesystem::exists(db("no_choice"))) << "nothing is written for a refused sweep";
  EXPECT_FALSE(std::filesystem::exists(db("no_choice") + ".array.sbatch"));
}

TEST_F(CmdRunEndEffector, UnknownLinkOnAGridAxisIsRefusedNamingTheAxisValue) {
  const std::string spec = write_spec("unknown", "", R"("grid": {"end_effector.link": ["tool_tcp", "flange"]})");
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("unknown"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_EQ(result.output.rfind("armfarm: " + spec + ": sweep.grid[\"end_effector.link\"][1]: ", 0), 0u) << result.output;
  EXPECT_NE(result.output.find("no link 'flange' (leaf links: 'iiwa_link_ee', 'tool_tcp')"), std::string::npos) << result.output;
  EXPECT_EQ(count_lines(result.output), 1) << result.output;
  EXPECT_FALSE(std::filesystem::exists(db("unknown")));
}

}  // namespace
