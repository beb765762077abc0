// `armfarm run` as a user reads it (fake jobs): heartbeat lines with an ETA in a log, --quiet,
// the closing summary with the main metric, `armfarm --version`; and truthful progress under a
// full disk: no job printed `done` that the database does not hold, the run stops saying how
// many finished jobs were lost, and the next run reruns exactly the jobs that are not saved.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

CommandResult run_armfarm(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_FAKE_JOBS_BINARY) + " " + arguments;
  return run_command_line(command);
}

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
  const CommandResult result = run_armfarm("run " + path("p.json") + " --db " + path("p.db") + " -j 2 --heartbeat 0.03");
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

  const CommandResult quiet = run_armfarm("run " + path("p.json") + " --db " + path("q.db") + " -j 2 --quiet --heartbeat 0.01");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("progress:"), std::string::npos) << quiet.output;
  EXPECT_EQ(quiet.output.find("] done"), std::string::npos) << quiet.output;
  EXPECT_NE(quiet.output.find("sweep p: 12 done"), std::string::npos) << quiet.output;
}

TEST_F(CmdRunProgressTest, VersionExitsZero) {
  const CommandResult result = run_armfarm("--version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.rfind("armfarm ", 0), 0u) << result.output;
  EXPECT_EQ(run_armfarm("version").exit_code, 0);
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
  const CommandResult full = run_armfarm("run " + path("full.json") + " --db " + db + " -j 2 --heartbeat 0");
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
  ASSERT_EQ(run_armfarm("lease " + db + " 0.5").exit_code, 0);
  const CommandResult resumed = run_armfarm("run " + path("full.json") + " --db " + db + " -j 2 --heartbeat 0");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find(std::to_string(stored.size()) + " already done (skipped)"), std::string::npos)
      << resumed.output;
  EXPECT_EQ(find_printed_done(resumed.output), not_done) << resumed.output;
  EXPECT_EQ(find_stored(db, "full", true).size(), 30u);
  EXPECT_EQ(ResultsStore::open(db, ResultsStore::Mode::read_only).check_integrity(), "ok");
}

}  // namespace
}  // namespace armfarm
