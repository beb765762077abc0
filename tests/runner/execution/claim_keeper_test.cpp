// Runners sharing one database through job claims (processes of the built binary, fake jobs):
// two runners started together on a fresh file split 24 jobs with every job run once; a runner
// killed with SIGKILL has its claims taken over after the (test-short) lease of the file and every
// job ends done exactly once; `status` lists the live claims with owner, host, pid and ages.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/scratch_file.hpp"
#include "support/text_file.hpp"
#include <sqlite3.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

// "sweep s24: 13 done, ..." -> 13.
int parse_done(const std::string& output) {
  std::smatch match;
  if (!std::regex_search(output, match, std::regex(R"(sweep s24: (\d+) done,)"))) return -1;
  return std::stoi(match[1]);
}

int count_status(const std::string& db, const std::string& status) {
  try {
    const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
    const auto counts = store.count_jobs_by_status("s24");
    return counts.count(status) ? counts.at(status) : 0;
  } catch (const StoreError&) {
    return 0;  // not created yet
  }
}

class CmdRunClaimsTest : public test_support::ScratchFolderTest {
 protected:
  CmdRunClaimsTest() : ScratchFolderTest("claims") {}
  void SetUp() override {
    std::ofstream(path("s24.json")) << R"({"name": "s24", "base": {"fake": {"sleep_ms": 40}},
        "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60]}, "repeat": 4}})";
  }
  std::pair<pid_t, std::vector<std::string>> kill_a_runner_mid_sweep(const std::string& db);
};

TEST_F(CmdRunClaimsTest, TwoRunnersOnOneFreshDatabaseRunEveryJobOnce) {
  const std::string db = path("shared.db");
  // Started together: both also create the schema of the fresh file at the same moment.
  const test_support::ArmfarmProcess a = test_support::start_armfarm({"run", path("s24.json"), "--db", db, "-j", "2"}, path("a.txt"));
  const test_support::ArmfarmProcess b = test_support::start_armfarm({"run", path("s24.json"), "--db", db, "-j", "2"}, path("b.txt"));
  EXPECT_EQ(test_support::wait_armfarm(a), 0) << test_support::read_text_file(a.output_path);
  EXPECT_EQ(test_support::wait_armfarm(b), 0) << test_support::read_text_file(b.output_path);
  const std::string out_a = test_support::read_text_file(a.output_path), out_b = test_support::read_text_file(b.output_path);
  // Each job was run by one of them: the two summaries add up to the sweep.
  EXPECT_EQ(parse_done(out_a) + parse_done(out_b), 24) << out_a << out_b;

  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("s24");
  ASSERT_EQ(jobs.size(), 24u);
  for (const JobRecord& job : jobs) {
    EXPECT_EQ(job.status, "done") << job.key;
    EXPECT_EQ(job.attempts, 1) << job.key;
  }
  EXPECT_TRUE(store.find_job_claims(make_utc_timestamp(), false).empty());  // all released, none taken over
  EXPECT_EQ(store.check_integrity(), "ok");
}

// Starts a runner on `db` and SIGKILLs it after 4 jobs are done; returns its pid and the keys of
// the jobs it held (claimed and running) when it died.
std::pair<pid_t, std::vector<std::string>> CmdRunClaimsTest::kill_a_runner_mid_sweep(const std::string& db) {
  // The file's lease, 1 s for this test, for both runners.
  EXPECT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"lease", db, "1"}, path("lease.txt"))), 0) << test_support::read_text_file(path("lease.txt"));
  const test_support::ArmfarmProcess victim = test_support::start_armfarm({"run", path("s24.json"), "--db", db, "-j", "2"}, path("v.txt"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  // Killed while it holds a job: after 4 are done, at a moment a job is running.
  while ((count_status(db, "done") < 4 || count_status(db, "running") == 0) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(victim.pid, SIGKILL);
  EXPECT_EQ(test_support::wait_armfarm(victim), 128 + SIGKILL) << "the sweep ended before it could be killed";
  std::vector<std::string> held;
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  for (const JobClaimRecord& claim : store.find_job_claims(make_utc_timestamp())) {
    EXPECT_EQ(claim.pid, victim.pid);
    held.push_back(claim.key);
  }
  EXPECT_EQ(count_status(db, "running"), static_cast<int>(held.size()));
  return {victim.pid, held};
}

TEST_F(CmdRunClaimsTest, AKilledRunnersClaimsOnThisHostAreTakenOverWithoutWaitingForTheTimeout) {
  const std::string db = path("killed_local.db");
  const auto [victim_pid, held] = kill_a_runner_mid_sweep(db);
  ASSERT_FALSE(held.empty()) << "killed between jobs: nothing to take over";
  // The default timeout is 60 s: the dead pid on this host, not the heartbeat's age, frees the claims.
  const auto start_time = std::chrono::steady_clock::now();
  const test_support::ArmfarmProcess survivor = test_support::start_armfarm({"run", path("s24.json"), "--db", db, "-j", "2"}, path("s.txt"));
  const int survivor_exit = test_support::wait_armfarm(survivor);
  const std::string out = test_support::read_text_file(survivor.output_path);
  EXPECT_EQ(survivor_exit, 0) << out;
  EXPECT_NE(out.find(std::to_string(held.size()) + " stale claims of stopped runners taken over"), std::string::npos) << out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count(), 45.0);
  EXPECT_EQ(count_status(db, "done"), 24);
}

TEST_F(CmdRunClaimsTest, AKilledRunnersClaimsAreTakenOverAfterTheTimeout) {
  const std::string db = path("killed.db");
  const auto [victim_pid, held] = kill_a_runner_mid_sweep(db);
  const pid_t victim_pid_copy = victim_pid;
  ASSERT_FALSE(held.empty()) << "killed between jobs: nothing to take over";
  // As if the killed runner had run on another machine: only the heartbeat's age can free its claims.
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(raw, "UPDATE job_claims SET host = 'another-machine'", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(raw);

  // Started at once, the survivor sees the claims live, waits out the 1 s timeout, takes them over.
  const auto start_time = std::chrono::steady_clock::now();
  const test_support::ArmfarmProcess survivor = test_support::start_armfarm({"run", path("s24.json"), "--db", db, "-j", "2"}, path("s.txt"));
  const int survivor_exit = test_support::wait_armfarm(survivor);
  const std::string out = test_support::read_text_file(survivor.output_path);
  EXPECT_EQ(survivor_exit, 0) << out;
  EXPECT_NE(out.find(std::to_string(held.size()) + " stale claims of stopped runners taken over"), std::string::npos) << out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count(), 15.0);

  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("s24");
  ASSERT_EQ(jobs.size(), 24u);
  for (const JobRecord& job : jobs) {
    EXPECT_EQ(job.status, "done") << job.key;
    const bool was_held = std::find(held.begin(), held.end(), job.key) != held.end();
    EXPECT_EQ(job.attempts, was_held ? 2 : 1) << job.key;  // started twice only when killed mid-job
  }
  const std::vector<JobClaimRecord> claims = store.find_job_claims(make_utc_timestamp(), false);
  ASSERT_EQ(claims.size(), held.size());
  for (const JobClaimRecord& claim : claims) {
    EXPECT_EQ(claim.state, "interrupted");
    EXPECT_EQ(claim.pid, victim_pid_copy);
  }
  const test_support::ArmfarmProcess query = test_support::start_armfarm({"status", db}, path("status.txt"));
  EXPECT_EQ(test_support::wait_armfarm(query), 0);
  const std::string status = test_support::read_text_file(query.output_path);
  EXPECT_NE(status.find("interrupted claims: " + std::to_string(held.size())), std::string::npos) << status;
  EXPECT_EQ(status.find("live claims"), std::string::npos) << status;
}

TEST_F(CmdRunClaimsTest, StatusShowsTheLiveClaimsOfARunningSweep) {
  std::ofstream(path("slow.json")) << R"({"name": "slow", "base": {"fake": {"sleep_ms": 5000}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20]}}})";
  const std::string db = path("slow.db");
  const test_support::ArmfarmProcess runner = test_support::start_armfarm({"run", path("slow.json"), "--db", db, "-j", "2"}, path("r.txt"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::string status;
  while (std::chrono::steady_clock::now() < deadline) {
    const test_support::ArmfarmProcess query = test_support::start_armfarm({"status", db}, path("status.txt"));
    test_support::wait_armfarm(query);
    status = test_support::read_text_file(query.output_path);
    if (status.find("live claims: 2") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(runner.pid, SIGINT);
  EXPECT_EQ(test_support::wait_armfarm(runner), 1);
  EXPECT_NE(status.find("live claims: 2"), std::string::npos) << status;
  EXPECT_NE(status.find(" pid " + std::to_string(runner.pid) + ": running "), std::string::npos) << status;
  EXPECT_NE(status.find(" owner "), std::string::npos) << status;
  EXPECT_NE(status.find(" host "), std::string::npos) << status;
  EXPECT_NE(status.find("heartbeat "), std::string::npos) << status;
  // Ctrl-C released them: nothing live afterwards, both jobs back to pending.
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  EXPECT_TRUE(store.find_job_claims(make_utc_timestamp()).empty());
  EXPECT_EQ(store.count_jobs_by_status("slow").at("pending"), 2);
}

}  // namespace
}  // namespace armfarm
