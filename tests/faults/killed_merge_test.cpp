// Issue 30, case 5 (the merge half), reproduced with processes of the built binary: a merge of two
// shard files killed with SIGKILL at random moments (until 20 kills land mid-merge) never leaves an OUT that is a part of the
// merge (OUT is absent, or has every job of the two shards, done, and passes check_contents), and
// merging the same files again adds no job and no `runs` row twice.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/scratch_file.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sqlite3.h>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;
using test_support::read_output;
using test_support::start_armfarm;
using test_support::wait_armfarm;

int count_rows(const std::string& db, const std::string& table) {
  sqlite3* raw = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(raw, ("SELECT count(*) FROM " + table).c_str(), -1, &statement, nullptr), SQLITE_OK);
  const int n = sqlite3_step(statement) == SQLITE_ROW ? sqlite3_column_int(statement, 0) : -1;
  sqlite3_finalize(statement);
  sqlite3_close(raw);
  return n;
}

TEST(KilledMerge, AMergeKilledAnywhereNeverLeavesAFileThatLooksComplete) {
  const fs::path folder = test_support::make_scratch_folder("faults_merge");
  const auto path = [&](const std::string& name) { return (folder / name).string(); };
  std::ofstream(path("m.json")) << R"({"name": "m", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60, 70, 80]}, "repeat": 5}})";
  for (const char* shard : {"1/2", "2/2"}) {
    const std::string db = path(std::string("shard") + shard[0] + ".db");
    const auto run = start_armfarm({"run", path("m.json"), "--db", db, "--shard", shard, "-q"}, path("run.txt"));
    ASSERT_EQ(wait_armfarm(run), 0) << read_output(run);
  }
  const std::string out = path("out.db");
  std::mt19937 random(30);
  std::uniform_int_distribution<int> moment_us(0, 150000);
  int killed_while_running = 0;
  // Until 20 kills landed while a merge ran (a merge that ended first is looked at as well).
  for (int trial = 0; trial < 100 && killed_while_running < 20; ++trial) {
    const auto merge = start_armfarm({"merge", out, path("shard1.db"), path("shard2.db")}, path("merge.txt"));
    std::this_thread::sleep_for(std::chrono::microseconds(moment_us(random)));
    kill(merge.pid, SIGKILL);
    const int exit_code = wait_armfarm(merge);
    if (exit_code == 128 + SIGKILL) ++killed_while_running;
    if (!fs::exists(out)) continue;  // cut short before the rename: nothing there
    const ResultsStore store = ResultsStore::open(out, ResultsStore::Mode::read_only);
    const std::map<std::string, int> counts = store.count_jobs_by_status("m");
    EXPECT_EQ(counts.size(), 1u) << "trial " << trial;
    EXPECT_EQ(counts.count("done") ? counts.at("done") : 0, 40) << "trial " << trial;  // before: 20 of 40
    EXPECT_TRUE(store.check_contents(true).empty()) << "trial " << trial;
    EXPECT_EQ(count_rows(out, "runs"), 2) << "trial " << trial;  // one per shard, however often merged
  }
  EXPECT_GE(killed_while_running, 20);
  // Merged to the end, twice: the second adds nothing (before: runs rows 5 -> 9).
  for (int again = 0; again < 2; ++again) {
    const auto merge = start_armfarm({"merge", out, path("shard1.db"), path("shard2.db")}, path("merge.txt"));
    ASSERT_EQ(wait_armfarm(merge), 0) << read_output(merge);
    EXPECT_EQ(count_rows(out, "jobs"), 40);
    EXPECT_EQ(count_rows(out, "runs"), 2);
    EXPECT_EQ(count_rows(out, "metrics"), count_rows(path("shard1.db"), "metrics") + count_rows(path("shard2.db"), "metrics"));
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
