// Issue 30, cases 5, 6, 7 and 8 as the commands show them (processes of the built binary, fake
// jobs): `status` counts a partial merge against the expansion of the sweep's stored spec ("20 of
// 40") and names what is missing; a runner killed with SIGKILL leaves claims and a `runs` row that
// `status` calls died, not running; `run` refuses a damaged file before adding to it; a FIFO as
// the database blocks no command; a spec nested 10^5 levels deep is refused at once.
#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/scratch_file.hpp"

#include <sqlite3.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;
using test_support::read_output;
using test_support::start_armfarm;
using test_support::wait_armfarm;

class VisibleStateTest : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = test_support::make_scratch_folder("faults_visible"); }
  void TearDown() override { fs::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  int armfarm(const std::vector<std::string>& arguments, std::string& output) const {
    const auto process = start_armfarm(arguments, path("out.txt"));
    const int code = wait_armfarm(process);
    output = read_output(process);
    return code;
  }
  void execute_sql(const std::string& db, const std::string& sql) const {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
    char* error = nullptr;
    EXPECT_EQ(sqlite3_exec(handle, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
    sqlite3_free(error);
    sqlite3_close(handle);
  }
  /// Runs a sweep `name` of two 1 ms fake jobs into NAME.db and returns that file's path.
  std::string run_two_fake_jobs(const std::string& name) const {
    std::ofstream(path(name + ".json")) << R"({"name": ")" << name << R"(", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20]}}})";
    const std::string db = path(name + ".db");
    std::string output;
    EXPECT_EQ(armfarm({"run", path(name + ".json"), "--db", db, "-q"}, output), 0) << output;
    return db;
  }
  fs::path folder_;
};

// Case 5: a merge of one shard of two said "20 jobs, 20 done" of 40.
TEST_F(VisibleStateTest, StatusCountsAPartialMergeAgainstTheStoredSpec) {
  std::ofstream(path("m.json")) << R"({"name": "m", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60, 70, 80]}, "repeat": 5}})";
  std::string output;
  for (const char* shard : {"1/2", "2/2"}) {
    const std::string db = path(std::string("shard") + shard[0] + ".db");
    ASSERT_EQ(armfarm({"run", path("m.json"), "--db", db, "--shard", shard, "-q"}, output), 0) << output;
  }
  ASSERT_EQ(armfarm({"merge", path("half.db"), path("shard1.db")}, output), 0) << output;
  EXPECT_EQ(armfarm({"status", path("half.db")}, output), 1) << output;
  EXPECT_NE(output.find("sweep m: 20 of 40 jobs in this file, 20 done"), std::string::npos) << output;
  EXPECT_NE(output.find("  missing: 20 jobs of its spec are not in this file (a shard not merged?): "), std::string::npos)
      << output;
  EXPECT_NE(output.find(" ... and 17 more\n"), std::string::npos) << output;
  EXPECT_NE(output.find("learning.lwpr.init_D="), std::string::npos) << output;  // named by their parameters

  ASSERT_EQ(armfarm({"merge", path("half.db"), path("shard2.db")}, output), 0) << output;
  EXPECT_EQ(armfarm({"status", path("half.db")}, output), 0) << output;
  EXPECT_NE(output.find("sweep m: 40 jobs, 40 done ("), std::string::npos) << output;
  EXPECT_EQ(output.find("missing"), std::string::npos) << output;
}

// Case 8: a SIGKILLed runner's claims showed as "running" and its `runs` row stayed `running`.
TEST_F(VisibleStateTest, ADeadRunnersClaimsAndRunAreShownAsNotRunning) {
  std::ofstream(path("k.json")) << R"({"name": "k", "base": {"fake": {"sleep_ms": 60000}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20]}}})";
  const std::string db = path("k.db");
  const auto runner = start_armfarm({"run", path("k.json"), "--db", db, "-j", "2"}, path("runner.txt"));
  std::string output;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    armfarm({"status", db}, output);
    if (output.find("live claims: 2") != std::string::npos) break;
  }
  ASSERT_NE(output.find("live claims: 2"), std::string::npos) << output;
  EXPECT_NE(output.find("2 running"), std::string::npos) << output;
  EXPECT_NE(output.find("runs not closed: 1"), std::string::npos) << output;
  EXPECT_NE(output.find(" pid " + std::to_string(runner.pid) + ", started "), std::string::npos) << output;
  ASSERT_EQ(kill(runner.pid, SIGKILL), 0);
  wait_armfarm(runner);

  EXPECT_EQ(armfarm({"status", db}, output), 0) << output;
  EXPECT_NE(output.find("sweep k: 2 jobs, 2 stale (runner stopped)"), std::string::npos) << output;
  EXPECT_EQ(output.find(": running"), std::string::npos) << output;  // before: "pid P: running 3.2 s"
  const std::string died = "died: runner ";
  EXPECT_NE(output.find(" pid " + std::to_string(runner.pid) + ": " + died), std::string::npos) << output;
  EXPECT_NE(output.find("is gone (no such process on this host)"), std::string::npos) << output;
  EXPECT_NE(output.find("runs not closed: 1\n  run 1 of sweep k host "), std::string::npos) << output;

  // On another host only the heartbeat's age can tell: past the lease it is stale.
  execute_sql(db,
              "UPDATE job_claims SET host = 'another-machine', heartbeat_at = '2020-01-01T00:00:00.000Z'; "
              "UPDATE runs SET host = 'another-machine', heartbeat_at = '2020-01-01T00:00:00.000Z'");
  EXPECT_EQ(armfarm({"status", db}, output), 0) << output;
  EXPECT_NE(output.find("stale: no heartbeat for "), std::string::npos) << output;
  EXPECT_NE(output.find(", over the file's lease of 60 s (runner another-machine pid " + std::to_string(runner.pid)),
            std::string::npos)
      << output;
  EXPECT_EQ(output.find(": running"), std::string::npos) << output;
}

// Case 6: `run` added to a file with dangling metric rows and exited 0.
TEST_F(VisibleStateTest, RunRefusesADamagedDatabaseBeforeAddingToIt) {
  const std::string db = run_two_fake_jobs("d");
  ASSERT_FALSE(HasFailure());
  std::string output;
  execute_sql(db, "PRAGMA foreign_keys = OFF; DELETE FROM sweep_jobs WHERE job_id = 1; DELETE FROM jobs WHERE id = 1");
  const auto before = fs::last_write_time(db);
  const auto size = fs::file_size(db);
  EXPECT_EQ(armfarm({"run", path("d.json"), "--db", db, "-q"}, output), 2) << output;
  EXPECT_EQ(output.rfind("armfarm: " + db + ": damaged armfarm database: ", 0), 0u) << output;
  EXPECT_NE(output.find("refers to a missing row of jobs"), std::string::npos) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  EXPECT_EQ(fs::last_write_time(db), before);
  EXPECT_EQ(fs::file_size(db), size);
  EXPECT_FALSE(fs::exists(db + "-wal") && fs::file_size(db + "-wal") > 0);
  // compare reads the same way.
  EXPECT_EQ(armfarm({"compare", db, db}, output), 2) << output;
  EXPECT_NE(output.find("damaged armfarm database"), std::string::npos) << output;
}

// Case 6: `status --check` passed a jobs.status of 'weird'; plain `status` showed it as a count.
TEST_F(VisibleStateTest, StatusRefusesAnUnknownJobStatus) {
  const std::string db = run_two_fake_jobs("w");
  ASSERT_FALSE(HasFailure());
  std::string output;
  execute_sql(db, "PRAGMA ignore_check_constraints = ON; UPDATE jobs SET status = 'weird' WHERE id = 1");
  EXPECT_EQ(armfarm({"status", "--check", db}, output), 2) << output;
  EXPECT_NE(output.find("status 'weird' is not a job status"), std::string::npos) << output;
  EXPECT_EQ(armfarm({"status", db}, output), 2) << output;
  EXPECT_EQ(output.rfind("armfarm: " + db + ": damaged armfarm database: ", 0), 0u) << output;
}

// Case 7: a FIFO as --db blocked status, run, table, compare, export and merge (ctest's timeout
// ends a hang here).
TEST_F(VisibleStateTest, AFifoAsTheDatabaseBlocksNoCommand) {
  const std::string fifo = path("fifo.db");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::ofstream(path("f.json")) << R"({"name": "f", "base": {"fake": {"sleep_ms": 1}}})";
  std::string ran;
  ASSERT_EQ(armfarm({"run", path("f.json"), "--db", path("in.db"), "-q"}, ran), 0) << ran;
  const std::vector<std::vector<std::string>> commands = {
      {"status", fifo}, {"run", path("f.json"), "--db", fifo}, {"table", fifo}, {"compare", fifo, fifo},
      {"export", fifo, "--sweep", "f"}, {"merge", path("out.db"), fifo}, {"merge", fifo, path("in.db")}};
  for (const std::vector<std::string>& command : commands) {
    std::string output;
    EXPECT_EQ(armfarm(command, output), 2) << command[0] << ": " << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << command[0] << ": " << output;
  }
  EXPECT_FALSE(fs::exists(path("out.db")));
}

// Case 7: a 200 KB spec nested 10^5 levels deep grew memory by 40 MB/s. Refused at the 257th
// bracket; the CPU time the refusal costs the child (not wall time: the machine may be loaded) is
// that of starting the binary.
TEST_F(VisibleStateTest, ADeepSpecIsRefusedAtOnce) {
  std::ofstream(path("deep.json")) << "{\"name\": " << std::string(100000, '[') << std::string(100000, ']') << "}";
  rusage before{};
  getrusage(RUSAGE_CHILDREN, &before);
  std::string output;
  EXPECT_EQ(armfarm({"expand", path("deep.json")}, output), 2) << output;
  rusage after{};
  getrusage(RUSAGE_CHILDREN, &after);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  const double cpu = seconds(after.ru_utime) - seconds(before.ru_utime) + seconds(after.ru_stime) - seconds(before.ru_stime);
  EXPECT_EQ(output, "armfarm: " + path("deep.json") +
                        ": line 1, column 265: arrays and objects nest deeper than 256 levels (the most a spec may nest)\n");
  EXPECT_LT(cpu, 0.1) << "CPU seconds";
  EXPECT_LT(after.ru_maxrss, 200 * 1024) << "peak kB of the children";
}

}  // namespace
}  // namespace armfarm
