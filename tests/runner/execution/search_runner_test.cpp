// `armfarm run` on a spec with a search (fake jobs): the trial sequence stored in search_steps
// (trial, rung, visibility, kind, job key, objective) is identical at -j1 and -j2 and after a
// runner is killed with SIGKILL mid-search and resumed at another thread count; a random search
// whose jobs a TPE search of the same seed already ran still records its sweep and steps; a
// real job's held-out objective without learning.heldout_checkpoints is read at its default
// checkpoint (never undefined for every trial); an ASHA promotion of a batch job (each rung a
// job that trains to its checkpoint's epoch) scores bit-identically to one straight run.
#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/scratch_file.hpp"
#include "support/sqlite_rows.hpp"

#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

using test_support::query_rows;

const char* const kSteps =
    "SELECT st.step, st.trial, st.rung, st.visible, st.kind, j.key, st.objective, t.params FROM search_steps st "
    "JOIN jobs j ON j.id = st.job_id JOIN search_trials t ON t.search_id = st.search_id AND t.trial = st.trial "
    "ORDER BY st.step";

class CmdRunSearchTest : public test_support::ScratchFolderTest {
 protected:
  CmdRunSearchTest() : ScratchFolderTest("run_search") {}
  void SetUp() override {
    std::ofstream(path("search.json")) << R"({"name": "fake search", "base": {"fake": {"sleep_ms": 80}},
      "sweep": {"search": {"method": "tpe", "seed": 3, "slots": 2,
        "objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}, "learning.lwpr.init_D": {"log_uniform": [0.01, 100]}},
        "budget": {"jobs": 14}}}})";
  }
  int run(const std::string& db, const std::string& threads) {
    return test_support::wait_armfarm(test_support::start_armfarm({"run", path("search.json"), "--db", db, "-j", threads, "-q"},
                                path(db.substr(db.rfind('/') + 1) + ".txt")));
  }
};

TEST_F(CmdRunSearchTest, TheTrialSequenceIsTheSameAtJ1J2AndAfterAKillAndResume) {
  ASSERT_EQ(run(path("j1.db"), "1"), 0);
  const std::vector<std::string> reference = query_rows(path("j1.db"), kSteps);
  ASSERT_EQ(reference.size(), 14u);  // the budget: 14 jobs
  EXPECT_EQ(query_rows(path("j1.db"), "SELECT count(*) FROM search_steps WHERE committed = 1"), std::vector<std::string>{"14"});
  ASSERT_EQ(run(path("j2.db"), "2"), 0);
  EXPECT_EQ(query_rows(path("j2.db"), kSteps), reference);

  // Killed once 5 jobs are done, while jobs run; resumed at -j1.
  const std::string killed = path("killed.db");
  const test_support::ArmfarmProcess victim = test_support::start_armfarm({"run", path("search.json"), "--db", killed, "-j", "2", "-q"}, path("victim.txt"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::vector<std::string> done = query_rows(killed, "SELECT count(*) FROM jobs WHERE status = 'done'");
    if (!done.empty() && std::stoi(done[0]) >= 5) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(victim.pid, SIGKILL);
  ASSERT_EQ(test_support::wait_armfarm(victim), 128 + SIGKILL) << "the search ended before it could be killed";
  ASSERT_LT(std::stoi(query_rows(killed, "SELECT count(*) FROM search_steps WHERE committed = 1").at(0)), 14);
  ASSERT_EQ(run(killed, "1"), 0);
  EXPECT_EQ(query_rows(killed, kSteps), reference);
}

TEST_F(CmdRunSearchTest, ARandomSearchOfJobsAnotherSweepRanIsStillRecorded) {
  // Below TPE's 10 startup trials its proposals are the prior draws random search makes from
  // the same seed: the random search's 6 jobs are all done before it starts.
  std::ofstream(path("tpe.json")) << R"({"name": "tpe six", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"search": {"method": "tpe", "seed": 5, "objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}}, "budget": {"jobs": 6}}}})";
  std::ofstream(path("random.json")) << R"({"name": "random six", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"search": {"method": "random", "seed": 5, "objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}}, "budget": {"jobs": 6}}}})";
  const std::string db = path("shared.db");
  ASSERT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"run", path("tpe.json"), "--db", db, "-j", "1", "-q"}, path("tpe.txt"))), 0);
  ASSERT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"run", path("random.json"), "--db", db, "-j", "1", "-q"}, path("random.txt"))), 0);
  EXPECT_EQ(query_rows(db, "SELECT count(*) FROM jobs"), std::vector<std::string>{"6"});  // the same six jobs
  EXPECT_EQ(query_rows(db, "SELECT s.name, count(st.step), sum(st.committed), count(st.objective) FROM searches se "
                      "JOIN sweeps s ON s.id = se.sweep_id JOIN search_steps st ON st.search_id = se.id "
                      "GROUP BY s.name ORDER BY s.name"),
            (std::vector<std::string>{"random six|6|6|6", "tpe six|6|6|6"}));
}

TEST_F(CmdRunSearchTest, AHeldOutObjectiveWithoutCheckpointsIsReadAtTheDefaultOne) {
  // A short batch-learning job (two collection passes of a 2 s sine on joints 1-2); the spec
  // sets no learning.heldout_checkpoints, as sweeps/search/fig6_1_kernel_width_tpe.json.
  std::ofstream(path("real.json")) << R"({"name": "real two", "base": {"active_joints": [1, 2],
      "trajectory": {"kind": "sine", "sine": {"amplitude": [0.22, 0.2], "frequency": [0.5, 1.0], "phase": [0, 0], "duration": 2.0}},
      "control": {"mode": "composite", "feed_forward": "learner", "gain_scale": 0.2},
      "learning": {"mode": "batch", "collect_repeats": 2, "train_fraction": 0.75}},
      "sweep": {"search": {"method": "random", "seed": 1, "objective": {"metric": "heldout_test_nmse", "joint": 2},
        "space": {"learning.lwpr.init_D": {"log_uniform": [0.05, 3.0]}}, "budget": {"jobs": 2}}}})";
  const std::string db = path("real.db");
  ASSERT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"run", path("real.json"), "--db", db, "-j", "1", "-q"}, path("real.txt"), false)), 0)
      << std::ifstream(path("real.txt")).rdbuf();
  // The objective each step saw is the stored metric's value at its (one, default) checkpoint.
  const std::vector<std::string> seen = query_rows(db, "SELECT st.objective IS NOT NULL, st.objective = m.value FROM search_steps st "
                                                  "JOIN job_metrics m ON m.job_id = st.job_id AND m.name = 'heldout_test_nmse' "
                                                  "AND m.joint = 2 ORDER BY st.step");
  EXPECT_EQ(seen, (std::vector<std::string>{"1|1", "1|1"}));
}

TEST_F(CmdRunSearchTest, APromotedTrialScoresAsAStraightRunToTheLongerBudget) {
  // ASHA over epochs 1/3/9 of a short batch job: a step to rung r is a job that trains
  // learning.epochs = rungs[r] epochs (the last rung: the base's 9). Batch training draws its
  // shuffles in epoch order from the job's seed, so a job cut after epoch e is a prefix of the
  // longer one and scores the same at every checkpoint it shares, bit for bit.
  const std::string base = R"("active_joints": [1, 2],
      "trajectory": {"kind": "sine", "sine": {"amplitude": [0.22, 0.2], "frequency": [0.5, 1.0], "phase": [0, 0], "duration": 2.0}},
      "control": {"mode": "composite", "feed_forward": "learner", "gain_scale": 0.2},
      "learning": {"mode": "batch", "collect_repeats": 2, "train_fraction": 0.75, "epochs": 9, "heldout_checkpoints": [1, 3, 9])";
  std::ofstream(path("asha.json")) << R"({"name": "asha epochs", "base": {)" + base + R"(}},
      "sweep": {"search": {"method": "asha", "seed": 2, "eta": 3, "slots": 1, "max_trials": 9,
        "objective": {"metric": "heldout_test_nmse", "joint": 2},
        "space": {"learning.lwpr.init_D": {"log_uniform": [0.05, 3.0]}}, "budget": {"jobs": 20}}}})";
  const std::string db = path("asha.db");
  ASSERT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"run", path("asha.json"), "--db", db, "-j", "1", "-q"}, path("asha.txt"), false)), 0)
      << std::ifstream(path("asha.txt")).rdbuf();
  // 9 new trials, and (asynchronous promotions, as in asha_test's hand-worked example) some of
  // them promoted to rung 1 and at least one to rung 2.
  const std::vector<std::string> rungs = query_rows(db, "SELECT rung, count(*) FROM search_steps GROUP BY rung ORDER BY rung");
  ASSERT_EQ(rungs.size(), 3u);
  EXPECT_EQ(rungs[0], "0|9");
  const std::vector<std::string> top = query_rows(db, "SELECT trial FROM search_steps WHERE rung = 2 ORDER BY step LIMIT 1");
  ASSERT_EQ(top.size(), 1u);
  // Each of that trial's jobs: its epochs and its objective at its own rung's checkpoint.
  const std::string per_rung =
      "SELECT st.rung, json_extract(j.config, '$.learning.epochs'), printf('%!.17g', st.objective) FROM search_steps st "
      "JOIN jobs j ON j.id = st.job_id WHERE st.trial = " + top[0] + " ORDER BY st.rung";
  const std::vector<std::string> steps = query_rows(db, per_rung);
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_EQ(steps[0].substr(0, 4), "0|1|");
  EXPECT_EQ(steps[1].substr(0, 4), "1|3|");
  EXPECT_EQ(steps[2].substr(0, 4), "2|9|");
  const std::string init_d = query_rows(db, "SELECT printf('%!.17g', json_extract(params, '$.\"learning.lwpr.init_D\"')) FROM search_trials "
                                       "WHERE trial = " + top[0]).at(0);

  // The straight run: the trial's point in a plain sweep, in a file of its own.
  std::ofstream(path("straight.json")) << R"({"name": "straight", "base": {)" + base + R"(, "lwpr": {"init_D": )" + init_d + R"(}}}})";
  const std::string straight = path("straight.db");
  ASSERT_EQ(test_support::wait_armfarm(test_support::start_armfarm({"run", path("straight.json"), "--db", straight, "-j", "1", "-q"}, path("straight.txt"), false)), 0)
      << std::ifstream(path("straight.txt")).rdbuf();
  const std::vector<std::string> checkpoints =
      query_rows(straight, "SELECT m.checkpoint, printf('%!.17g', m.value) FROM job_metrics m WHERE m.name = 'heldout_test_nmse' "
                      "AND m.joint = 2 ORDER BY m.checkpoint");
  ASSERT_EQ(checkpoints.size(), 3u);
  for (std::size_t r = 0; r < 3; ++r) {
    EXPECT_EQ(steps[r].substr(steps[r].rfind('|') + 1), checkpoints[r].substr(checkpoints[r].find('|') + 1))
        << "rung " << r << " against the straight run's checkpoint " << checkpoints[r];
  }
  // The last rung is the straight job itself: the same key.
  EXPECT_EQ(query_rows(straight, "SELECT key FROM jobs"),
            query_rows(db, "SELECT j.key FROM search_steps st JOIN jobs j ON j.id = st.job_id WHERE st.rung = 2 AND st.trial = " + top[0]));
}

}  // namespace
}  // namespace armfarm
