// Issue 30, cases 1 and 2, reproduced as written with processes of the built binary (fake jobs):
// a runner paused with SIGSTOP past the file's lease and resumed with SIGCONT finds its claims
// taken over; its results are discarded by the store's fence (with --timeout and without), so
// every done result of the runner that took over stays and no result is written twice. A second
// runner cannot judge claims by a shorter timeout of its own: --claim-timeout is refused, and
// both runners of a file judge by its one lease, so a live runner's claims are never stolen.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/scratch_file.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sqlite3.h>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;
using test_support::read_output;
using test_support::start_armfarm;
using test_support::wait_armfarm;

// `runs` rows of the file with this status, read with plain sqlite3.
int count_runs(const std::string& db, const std::string& status) {
  sqlite3* raw = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(raw, "SELECT count(*) FROM runs WHERE status = ?", -1, &statement, nullptr), SQLITE_OK);
  sqlite3_bind_text(statement, 1, status.c_str(), -1, SQLITE_TRANSIENT);
  const int n = sqlite3_step(statement) == SQLITE_ROW ? sqlite3_column_int(statement, 0) : -1;
  sqlite3_finalize(statement);
  sqlite3_close(raw);
  return n;
}

class FencedClaimsTest : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = test_support::make_scratch_folder("faults_claims"); }
  void TearDown() override { fs::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  void write_spec(const std::string& name, int jobs, int sleep_ms) const {
    std::string values;
    for (int i = 0; i < jobs; ++i) values += (i ? ", " : "") + std::to_string(10 * (i + 1));
    std::ofstream(path(name + ".json")) << R"({"name": ")" << name << R"(", "base": {"fake": {"sleep_ms": )"
                                        << sleep_ms << R"(}}, "sweep": {"grid": {"learning.lwpr.init_D": [)" << values
                                        << "]}}}";
  }
  int run_to_end(const std::vector<std::string>& arguments, const std::string& output) const {
    return wait_armfarm(start_armfarm(arguments, path(output)));
  }
  // Runs case 1: two 2-second jobs, a runner paused after 1 s until a second runner finished both.
  void pause_a_runner_past_the_lease(const std::vector<std::string>& extra);
  fs::path folder_;
};

void FencedClaimsTest::pause_a_runner_past_the_lease(const std::vector<std::string>& extra) {
  write_spec("p", 2, 2000);
  const std::string db = path("p.db");
  ASSERT_EQ(run_to_end({"lease", db, "3"}, "lease.txt"), 0);
  std::vector<std::string> arguments = {"run", path("p.json"), "--db", db, "-j", "2"};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  const auto paused = start_armfarm(arguments, path("paused.txt"));
  // Paused once it holds both jobs (about 1 s in on an idle machine, as the issue did it).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::map<std::string, int> counts = ResultsStore::open(db, ResultsStore::Mode::read_only).count_jobs_by_status("p");
    if ((counts.count("running") && counts.at("running") == 2) || std::chrono::steady_clock::now() > deadline) break;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(kill(paused.pid, SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(3500));  // past the 3 s lease
  const auto other = start_armfarm({"run", path("p.json"), "--db", db, "-j", "2", "-q"}, path("other.txt"));
  EXPECT_EQ(wait_armfarm(other), 0) << read_output(other);
  EXPECT_NE(read_output(other).find("sweep p: 2 done,"), std::string::npos) << read_output(other);
  ASSERT_EQ(kill(paused.pid, SIGCONT), 0);
  const int paused_exit = wait_armfarm(paused);
  const std::string paused_text = read_output(paused);
  // It says what happened in one line, and counts it; its results are not the file's.
  // Each of its two jobs either finished and was discarded by the fence (said in one line), or
  // was stopped when its heartbeat found the claim gone and then found done by the other runner.
  std::smatch found;
  const int discarded =
      std::regex_search(paused_text, found, std::regex("sweep p: (\\d+) finished results discarded: another runner "
                                                       "took their claims over"))
          ? std::stoi(found[1])
          : 0;
  const int elsewhere =
      std::regex_search(paused_text, found, std::regex("(\\d+) done by another runner")) ? std::stoi(found[1]) : 0;
  EXPECT_EQ(discarded + elsewhere, 2) << paused_text;
  EXPECT_NE(paused_text.find("sweep p: 0 done,"), std::string::npos) << paused_text;  // it wrote nothing
  EXPECT_EQ(paused_exit, 0) << paused_text;

  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("p");
  ASSERT_EQ(jobs.size(), 2u);
  for (const JobRecord& job : jobs) {
    EXPECT_EQ(job.status, "done") << job.key;         // before: 2 timeout, 0 metric rows
    EXPECT_FALSE(store.find_metrics(job.id).empty()) << job.key;
    EXPECT_EQ(job.attempts, 2) << job.key;            // started twice (the pause), written once
  }
  // Written once: the finish time is the runner's that took over, before the paused one resumed.
  EXPECT_TRUE(store.find_job_claims(make_utc_timestamp(), true).empty());
  EXPECT_EQ(store.check_integrity(), "ok");
  // The paused runner's `runs` row stays as the other runner marked it (before: its last update
  // overwrote `interrupted` with `complete`).
  EXPECT_EQ(count_runs(db, "interrupted"), 1);
  EXPECT_EQ(count_runs(db, "complete"), 1);
}

TEST_F(FencedClaimsTest, APausedRunnerWithATimeoutDestroysNoFinishedResult) {
  pause_a_runner_past_the_lease({"--timeout", "5"});
}

TEST_F(FencedClaimsTest, APausedRunnerWithoutATimeoutOverwritesNoFinishedResult) {
  pause_a_runner_past_the_lease({});
}

// The exit code of a runner whose result was discarded (README.md, exit status): its job is the
// runner's that took the claim over; while that runner holds it (here: paused too) the job is
// not done in the file, and the discarding runner exits 1 and says so. Had its heartbeat noticed
// the take-over before the job finished, it waits for the claim instead (and, the other runner
// being paused past the lease, takes it back and finishes it: exit 0).
TEST_F(FencedClaimsTest, ARunnerWhoseDiscardedJobIsNotDoneElsewhereExitsOne) {
  write_spec("x", 1, 2000);
  const std::string db = path("x.db");
  ASSERT_EQ(run_to_end({"lease", db, "3"}, "lease.txt"), 0);
  const auto first = start_armfarm({"run", path("x.json"), "--db", db, "-j", "1"}, path("first.txt"));
  const auto holds = [&](pid_t pid) {
    for (const JobClaimRecord& claim : ResultsStore::open(db, ResultsStore::Mode::read_only).find_job_claims(make_utc_timestamp())) {
      if (claim.pid == pid) return true;
    }
    return false;
  };
  const auto wait_until_held_by = [&](pid_t pid) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!holds(pid) && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return holds(pid);
  };
  ASSERT_TRUE(wait_until_held_by(first.pid));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(kill(first.pid, SIGSTOP), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(3500));  // past the 3 s lease
  const auto second = start_armfarm({"run", path("x.json"), "--db", db, "-j", "1"}, path("second.txt"));
  const bool taken_over = wait_until_held_by(second.pid);
  kill(second.pid, SIGSTOP);
  ASSERT_TRUE(taken_over);
  ASSERT_EQ(kill(first.pid, SIGCONT), 0);
  const int first_exit = wait_armfarm(first);
  const std::string text = read_output(first);
  kill(second.pid, SIGKILL);
  kill(second.pid, SIGCONT);
  wait_armfarm(second);
  if (text.find("finished results discarded") != std::string::npos) {
    EXPECT_EQ(first_exit, 1) << text;
    EXPECT_NE(text.find("sweep x: 1 finished results discarded: another runner took their claims over"), std::string::npos)
        << text;
    EXPECT_NE(text.find(", and 1 of them are not done in the file yet (armfarm status " + db + ")\n"), std::string::npos)
        << text;
  } else {
    EXPECT_EQ(first_exit, 0) << text;
    EXPECT_NE(text.find("stale claims of stopped runners taken over"), std::string::npos) << text;
  }
  EXPECT_NE(first_exit, 3) << text;  // nothing of the file's was lost
}

TEST_F(FencedClaimsTest, APerRunnerClaimTimeoutIsRefused) {
  write_spec("q", 1, 10);
  const auto refused = start_armfarm({"run", path("q.json"), "--db", path("q.db"), "--claim-timeout", "3"},
                                     path("refused.txt"));
  EXPECT_EQ(wait_armfarm(refused), 2);
  const std::string text = read_output(refused);
  EXPECT_NE(text.find("--claim-timeout is gone: the lease is the database's"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_FALSE(fs::exists(path("q.db")));  // nothing written
}

// Case 2 with the lease the file's: six 2-second jobs, `-j3`, and 1 s later a second runner on the
// same file (lease 1.5 s, heartbeats every 0.25 s): it takes nothing over while the first runner
// lives, and every job is attempted once.
TEST_F(FencedClaimsTest, ASecondRunnerTakesOverNoLiveClaim) {
  write_spec("s", 6, 2000);
  const std::string db = path("s.db");
  ASSERT_EQ(run_to_end({"lease", db, "1.5"}, "lease.txt"), 0);
  const auto first = start_armfarm({"run", path("s.json"), "--db", db, "-j", "3"}, path("first.txt"));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const auto second = start_armfarm({"run", path("s.json"), "--db", db, "-j", "3"}, path("second.txt"));
  EXPECT_EQ(wait_armfarm(first), 0) << read_output(first);
  EXPECT_EQ(wait_armfarm(second), 0) << read_output(second);
  EXPECT_EQ(read_output(second).find("taken over"), std::string::npos) << read_output(second);
  EXPECT_EQ(read_output(first).find("discarded"), std::string::npos) << read_output(first);
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("s");
  ASSERT_EQ(jobs.size(), 6u);
  for (const JobRecord& job : jobs) {
    EXPECT_EQ(job.status, "done") << job.key;
    EXPECT_EQ(job.attempts, 1) << job.key;  // before: 4 of 6 with attempts 2
  }
}

}  // namespace
}  // namespace armfarm
