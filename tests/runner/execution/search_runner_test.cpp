// `armfarm run` on a spec with a search (fake jobs): the trial sequence stored in search_steps
// (trial, rung, visibility, kind, job key, objective) is identical at -j1 and -j2 and after a
// runner is killed with SIGKILL mid-search and resumed at another thread count; a random search
// whose jobs a TPE search of the same seed already ran still records its sweep and steps; a
// real job's held-out objective without learning.heldout_checkpoints is read at its default
// checkpoint (never undefined for every trial); a search recorded by a build before TPE's rule
// was stored (schema 7, no rule: the per-axis rule) continues with the per-axis rule; a joint
// search of schema 8 (no constants: version 8's) resumes and one recorded with other constants is
// refused; a cpu_seconds search resumed by a build with another cost factor takes its recorded
// rung costs and start-up and continues unchanged; an ASHA promotion of a batch job (each rung a
// job that trains to its checkpoint's epoch) scores bit-identically to one straight run.
#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/command_line.hpp"
#include "support/scratch_file.hpp"
#include "support/sqlite_rows.hpp"

#include "runner/execution/job_kind.hpp"
#include "runner/execution/search_runner.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
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

TEST_F(CmdRunSearchTest, TwoRunnersOnOneDatabaseTakeTheSameTrialSequenceAndRunEachJobOnce) {
  // The fixture's search with jobs of 0.3 s, so that the second process is surely running before
  // the first could finish alone.
  std::string text;
  {
    std::ifstream in(path("search.json"));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string fast = "\"sleep_ms\": 80";
  text.replace(text.find(fast), fast.size(), "\"sleep_ms\": 300");
  std::ofstream(path("slow.json")) << text;
  const auto start = [&](const std::string& db, const std::string& log) {
    return test_support::start_armfarm({"run", path("slow.json"), "--db", db, "-j", "1", "-q"}, path(log));
  };
  ASSERT_EQ(test_support::wait_armfarm(start(path("alone.db"), "alone.txt")), 0);
  const std::vector<std::string> reference = query_rows(path("alone.db"), kSteps);
  ASSERT_EQ(reference.size(), 14u);
  // Two processes started together on one new file, one thread each: they replay the same
  // decisions, share the jobs by their claims and record each step once.
  const std::string shared = path("shared_two.db");
  const test_support::ArmfarmProcess first = start(shared, "first.txt");
  const test_support::ArmfarmProcess second = start(shared, "second.txt");
  EXPECT_EQ(test_support::wait_armfarm(first), 0) << std::ifstream(path("first.txt")).rdbuf();
  EXPECT_EQ(test_support::wait_armfarm(second), 0) << std::ifstream(path("second.txt")).rdbuf();
  EXPECT_EQ(query_rows(shared, kSteps), reference);
  // No job ran twice, and both runners did some of them.
  EXPECT_EQ(query_rows(shared, "SELECT count(*), sum(attempts), sum(status = 'done') FROM jobs"),
            std::vector<std::string>{"14|14|14"});
  EXPECT_EQ(query_rows(shared, "SELECT count(DISTINCT pid) FROM runs WHERE jobs_run > 0"), std::vector<std::string>{"2"});
}

TEST_F(CmdRunSearchTest, ASearchIsNotShardedAndTheRefusalSaysWhy) {
  // A shard's file would lack the other shards' objectives, which each decision needs.
  const std::string spec = path("search.json");
  for (const std::string& command : {"run " + spec + " --db " + path("shard.db") + " --shard 1/2",
                                     "slurm " + spec + " --db " + path("shard.db") + " --tasks 2"}) {
    const test_support::CommandResult result = test_support::run_armfarm_with_fake_jobs(command);
    EXPECT_EQ(result.exit_code, 2) << command << "\n" << result.output;
    EXPECT_NE(result.output.find("armfarm: " + spec + ": sweep.search: a search is not sharded: each step is decided over the "
                                 "objectives of the steps before it"),
              std::string::npos)
        << command << "\n" << result.output;
    EXPECT_FALSE(fs::exists(path("shard.db"))) << command;
  }
}

TEST_F(CmdRunSearchTest, ARandomSearchOfJobsAnotherSweepRanIsStillRecorded) {
  // Below TPE's start-up (10 here, set in the spec: the budget rule would give 2) its proposals
  // are the prior draws random search makes from the same seed: the random search's 6 jobs are
  // all done before it starts.
  std::ofstream(path("tpe.json")) << R"({"name": "tpe six", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"search": {"method": "tpe", "seed": 5, "tpe_startup": 10, "objective": {"metric": "tracking_nmse", "joint": 1},
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

TEST_F(CmdRunSearchTest, TheFileKeepsWhatDecisionsDependOnAdoptsTheBuildsPartAndRefusesAChangedSpec) {
  // Six TPE jobs whose start-up the spec sets to 6: every trial a prior draw.
  const auto write = [&](const std::string& file, const std::string& startup, int budget) {
    std::ofstream(path(file)) << R"({"name": "kept", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"search": {"method": "tpe", "seed": 4, "slots": 2, )" + startup + R"("objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}, "learning.lwpr.init_D": {"log_uniform": [0.01, 100]}},
        "budget": {"jobs": )" + std::to_string(budget) + "}}}}";
  };
  write("six.json", R"("tpe_startup": 6, )", 6);
  const std::string db = path("kept.db");
  const auto run_spec = [&](const std::string& file) {
    return test_support::run_armfarm_with_fake_jobs("run " + path(file) + " --db " + db + " -j 1 -q");
  };
  ASSERT_EQ(run_spec("six.json").exit_code, 0);
  EXPECT_EQ(query_rows(db, "SELECT tpe_startup, tpe_gamma, tpe_max_good, tpe_candidates, max_trials, bracket_size, space FROM searches"),
            std::vector<std::string>{R"(6|0.25|25|24|0|0|[{"high":50.0,"kind":"uniform","low":0.5,"path":"control.gain_scale"},)"
                                     R"({"high":100.0,"kind":"log_uniform","low":0.01,"path":"learning.lwpr.init_D"}])"});
  const std::vector<std::string> steps = query_rows(db, kSteps);
  ASSERT_EQ(steps.size(), 6u);

  // The same spec without tpe_startup: the budget rule would give 2 (trials 2 … 5 from TPE, new
  // jobs); the runner takes the file's effective 6 and replays the same six steps, running nothing.
  write("rule.json", "", 6);
  const test_support::CommandResult adopted = run_spec("rule.json");
  EXPECT_EQ(adopted.exit_code, 0) << adopted.output;
  EXPECT_EQ(query_rows(db, kSteps), steps);
  EXPECT_EQ(query_rows(db, "SELECT count(*), sum(attempts) FROM jobs"), std::vector<std::string>{"6|6"});

  // What the spec decides must not change: refused before anything is written, one line each.
  write("other.json", R"("tpe_startup": 3, )", 8);
  const test_support::CommandResult refused = run_spec("other.json");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("armfarm: " + path("other.json") + ": sweep.search.budget: " + db +
                                " holds search 'kept' with budget 6 jobs, the spec gives 8 jobs; a search cannot change under its name"),
            std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("sweep.search.tpe_startup: " + db + " holds search 'kept' with tpe_startup 6, the spec gives 3;"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(query_rows(db, kSteps), steps);
  EXPECT_EQ(query_rows(db, "SELECT budget FROM searches"), std::vector<std::string>{"6.0"});
}

TEST_F(CmdRunSearchTest, ASearchRecordedWithoutATpeRuleResumesWithThePerAxisRule) {
  // The fixture's search (start-up 4 by the budget rule) with 1 ms jobs.
  std::string text;
  {
    std::ifstream in(path("search.json"));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string slow = "\"sleep_ms\": 80";
  text.replace(text.find(slow), slow.size(), "\"sleep_ms\": 1");
  std::ofstream(path("rule.json")) << text;
  // The per-axis run, in this process, the rule set on the settings (the spec's tpe_rule below).
  {
    const JobKind kind = make_job_kind();
    SweepSpec spec = load_sweep_spec(path("rule.json"), kind.schema);
    spec.search->settings.tpe.joint = false;
    RunOptions options;
    options.db_path = path("per_axis.db");
    options.threads = 1;
    const std::atomic<bool> stop{false};
    ASSERT_TRUE(run_search(spec, kind, options, ExpansionLimits{}, stop).finished);
  }
  const std::vector<std::string> per_axis = query_rows(path("per_axis.db"), kSteps);
  ASSERT_EQ(per_axis.size(), 14u);
  EXPECT_EQ(query_rows(path("per_axis.db"), "SELECT tpe_rule FROM searches"), std::vector<std::string>{"per_axis"});
  // The default (joint) run through the CLI: the same 4 prior draws, then other proposals.
  const auto run_rule = [&](const std::string& db) {
    return test_support::run_armfarm_with_fake_jobs("run " + path("rule.json") + " --db " + db + " -j 2 -q");
  };
  ASSERT_EQ(run_rule(path("joint.db")).exit_code, 0);
  const std::vector<std::string> joint = query_rows(path("joint.db"), kSteps);
  ASSERT_EQ(joint.size(), 14u);
  EXPECT_EQ(query_rows(path("joint.db"), "SELECT tpe_rule FROM searches"), std::vector<std::string>{"joint"});
  EXPECT_EQ(std::vector<std::string>(joint.begin(), joint.begin() + 4), std::vector<std::string>(per_axis.begin(), per_axis.begin() + 4));
  EXPECT_NE(joint, per_axis);
  // The per-axis search cut after 6 steps (2 of them TPE's), as a build of schema version 7 left
  // it: no tpe_rule column. Its 14 jobs stay in the file, so a resume that proposes anything else
  // runs new jobs. A copy with the rule "joint" shows that the rule decides the steps.
  const auto cut = [&](const std::string& db, const std::string& rule_sql) {
    fs::copy_file(path("per_axis.db"), db);
    query_rows(db, "DELETE FROM search_steps WHERE step >= 6; "
                   "DELETE FROM search_trials WHERE trial NOT IN (SELECT trial FROM search_steps); " + rule_sql);
    ASSERT_EQ(query_rows(db, "SELECT count(*) FROM search_steps"), std::vector<std::string>{"6"});
  };
  cut(path("old.db"), "ALTER TABLE searches DROP COLUMN tpe_rule; ALTER TABLE searches DROP COLUMN tpe_prior_weight; "
                      "ALTER TABLE searches DROP COLUMN tpe_bandwidth; ALTER TABLE searches DROP COLUMN tpe_liar_bandwidth; "
                      "PRAGMA user_version = 7;");
  cut(path("joint_label.db"), "UPDATE searches SET tpe_rule = 'joint';");
  const test_support::CommandResult resumed = run_rule(path("old.db"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(query_rows(path("old.db"), kSteps), per_axis);
  EXPECT_EQ(query_rows(path("old.db"), "SELECT count(*), sum(attempts) FROM jobs"), std::vector<std::string>{"14|14"});
  EXPECT_EQ(query_rows(path("old.db"), "SELECT tpe_rule FROM searches"), std::vector<std::string>{"per_axis"});  // written so
  EXPECT_EQ(query_rows(path("old.db"), "PRAGMA user_version"), std::vector<std::string>{"9"});
  // The per-axis rule uses none of the joint rule's constants: none recorded.
  EXPECT_EQ(query_rows(path("old.db"), "SELECT count(*) FROM searches WHERE tpe_prior_weight IS NULL AND tpe_bandwidth IS NULL "
                                       "AND tpe_liar_bandwidth IS NULL"),
            std::vector<std::string>{"1"});
  ASSERT_EQ(run_rule(path("joint_label.db")).exit_code, 0);
  const std::vector<std::string> relabelled = query_rows(path("joint_label.db"), kSteps);
  ASSERT_EQ(relabelled.size(), 14u);
  EXPECT_EQ(std::vector<std::string>(relabelled.begin(), relabelled.begin() + 6), std::vector<std::string>(per_axis.begin(), per_axis.begin() + 6));
  EXPECT_NE(relabelled, per_axis);
  EXPECT_NE(query_rows(path("joint_label.db"), "SELECT count(*) FROM jobs"), std::vector<std::string>{"14"});

  // The spec's tpe_rule chooses the rule: "per_axis" through the CLI takes the in-process
  // per-axis run's steps. Against a search recorded with the other rule it is refused.
  std::string per_axis_text = text;
  per_axis_text.insert(per_axis_text.find("\"method\": \"tpe\""), "\"tpe_rule\": \"per_axis\", ");
  std::ofstream(path("per_axis.json")) << per_axis_text;
  const test_support::CommandResult chosen =
      test_support::run_armfarm_with_fake_jobs("run " + path("per_axis.json") + " --db " + path("chosen.db") + " -j 2 -q");
  ASSERT_EQ(chosen.exit_code, 0) << chosen.output;
  EXPECT_EQ(query_rows(path("chosen.db"), kSteps), per_axis);
  const test_support::CommandResult against =
      test_support::run_armfarm_with_fake_jobs("run " + path("per_axis.json") + " --db " + path("joint.db") + " -j 2 -q");
  EXPECT_EQ(against.exit_code, 2) << against.output;
  EXPECT_NE(against.output.find("armfarm: " + path("per_axis.json") + ": sweep.search.tpe_rule: " + path("joint.db") +
                                " holds search 'fake search' with tpe_rule joint, the spec gives per_axis; a search cannot "
                                "change under its name"),
            std::string::npos)
      << against.output;
  EXPECT_EQ(query_rows(path("joint.db"), kSteps), joint);
}

TEST_F(CmdRunSearchTest, AJointSearchOfSchemaEightResumesAndOneWithOtherConstantsIsRefused) {
  // The fixture's search (joint rule, start-up 4 by the budget rule) with 1 ms jobs.
  std::string text;
  {
    std::ifstream in(path("search.json"));
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string slow = "\"sleep_ms\": 80";
  text.replace(text.find(slow), slow.size(), "\"sleep_ms\": 1");
  std::ofstream(path("joint.json")) << text;
  const auto run_joint = [&](const std::string& db) {
    return test_support::run_armfarm_with_fake_jobs("run " + path("joint.json") + " --db " + db + " -j 2 -q");
  };
  ASSERT_EQ(run_joint(path("joint.db")).exit_code, 0);
  const std::vector<std::string> joint = query_rows(path("joint.db"), kSteps);
  ASSERT_EQ(joint.size(), 14u);
  const std::string constants = "SELECT tpe_rule, tpe_prior_weight, tpe_bandwidth, tpe_liar_bandwidth FROM searches";
  EXPECT_EQ(query_rows(path("joint.db"), constants), std::vector<std::string>{"joint|1.0|0.2|0.7"});
  // The search cut after 6 steps (2 of them TPE's). As a build of schema version 8 left it: the
  // rule recorded, the constants not. Its 14 jobs stay in the file, so a resume that proposed
  // anything else would run new jobs.
  const auto cut = [&](const std::string& db, const std::string& sql) {
    fs::copy_file(path("joint.db"), db);
    query_rows(db, "DELETE FROM search_steps WHERE step >= 6; "
                   "DELETE FROM search_trials WHERE trial NOT IN (SELECT trial FROM search_steps); " + sql);
    ASSERT_EQ(query_rows(db, "SELECT count(*) FROM search_steps"), std::vector<std::string>{"6"});
  };
  cut(path("eight.db"), "ALTER TABLE searches DROP COLUMN tpe_prior_weight; ALTER TABLE searches DROP COLUMN tpe_bandwidth; "
                        "ALTER TABLE searches DROP COLUMN tpe_liar_bandwidth; PRAGMA user_version = 8;");
  const test_support::CommandResult resumed = run_joint(path("eight.db"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(query_rows(path("eight.db"), kSteps), joint);
  EXPECT_EQ(query_rows(path("eight.db"), "SELECT count(*), sum(attempts) FROM jobs"), std::vector<std::string>{"14|14"});
  EXPECT_EQ(query_rows(path("eight.db"), constants), std::vector<std::string>{"joint|1.0|0.2|0.7"});  // written so
  EXPECT_EQ(query_rows(path("eight.db"), "PRAGMA user_version"), std::vector<std::string>{"9"});

  // A row with another bandwidth fraction, as a build with other constants would write it:
  // refused in one line naming the database and the search, exit 2, nothing written.
  cut(path("other.db"), "UPDATE searches SET tpe_bandwidth = 0.3;");
  const std::string everything = "SELECT (SELECT group_concat(step || ':' || committed) FROM search_steps), "
                                 "(SELECT count(*) FROM runs), (SELECT sum(attempts) FROM jobs), (SELECT count(*) FROM search_trials)";
  const std::vector<std::string> before = query_rows(path("other.db"), everything);
  const test_support::CommandResult refused = run_joint(path("other.db"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  const std::string line = "armfarm: " + path("joint.json") + ": sweep.search: " + path("other.db") +
                           " holds search 'fake search' proposed by TPE's joint rule with prior weight 1, bandwidth 0.3 and liar "
                           "bandwidth 0.7, this build's are prior weight 1, bandwidth 0.2 and liar bandwidth 0.7; it would continue "
                           "with other proposals (resume it with a build of the file's constants, or give the sweep another name, "
                           "or use another database)\n";
  // The run's headline, then the refusal: one line.
  ASSERT_GE(refused.output.size(), line.size());
  EXPECT_EQ(refused.output.substr(refused.output.size() - line.size()), line) << refused.output;
  EXPECT_EQ(std::count(refused.output.begin(), refused.output.end(), '\n'), 2) << refused.output;
  EXPECT_EQ(query_rows(path("other.db"), everything), before);
  EXPECT_EQ(query_rows(path("other.db"), constants), std::vector<std::string>{"joint|1.0|0.3|0.7"});
}

// A cpu_seconds budget counts each job as the kind's estimate times the cost factor
// (calc_search_cpu_seconds; the fake job's estimate as it is). A build with another factor is a
// kind whose estimates are scaled: here half, as 0.0044 → 0.0021 did. Run afresh, it takes
// another search (twice the jobs, another start-up); resuming a search of the first build, it
// adopts the recorded rung cost and start-up and takes that search's steps, running nothing.
TEST_F(CmdRunSearchTest, ACpuSecondsSearchResumedByABuildWithAnotherCostFactorContinuesUnchanged) {
  // Fake jobs of 2 joints × 4 s + 1 ms: 8.001 each, so 56.01 buys 7 (and 14 at half the cost).
  std::ofstream(path("cpu.json")) << R"({"name": "cpu", "base": {"fake": {"sleep_ms": 1}},
      "sweep": {"search": {"method": "tpe", "seed": 5, "slots": 2,
        "objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}, "learning.lwpr.init_D": {"log_uniform": [0.01, 100]}},
        "budget": {"cpu_seconds": 56.01}}}})";
  const auto run_with = [&](const std::string& db, double scale) {
    JobKind kind = make_job_kind();
    const JobCostFunction estimate = kind.estimate_cost;
    kind.estimate_cost = [estimate, scale](const nlohmann::json& config, const CheckedConfig* checked) {
      JobCostEstimate e = estimate(config, checked);
      e.cost *= scale;
      return e;
    };
    const SweepSpec spec = load_sweep_spec(path("cpu.json"), kind.schema);
    RunOptions options;
    options.db_path = db;
    options.threads = 1;
    const std::atomic<bool> stop{false};
    return run_search(spec, kind, options, ExpansionLimits{}, stop);
  };
  const char* const kRow = "SELECT r.cost, se.tpe_startup FROM search_rungs r JOIN searches se ON se.id = r.search_id";
  ASSERT_TRUE(run_with(path("first.db"), 1.0).finished);
  const std::vector<std::string> first = query_rows(path("first.db"), kSteps);
  ASSERT_EQ(first.size(), 7u);
  EXPECT_EQ(query_rows(path("first.db"), kRow), std::vector<std::string>{"8.001|2"});
  ASSERT_TRUE(run_with(path("halved.db"), 0.5).finished);
  EXPECT_EQ(query_rows(path("halved.db"), kSteps).size(), 14u);
  EXPECT_EQ(query_rows(path("halved.db"), kRow), std::vector<std::string>{"4.0005|4"});
  // The first build's search cut after 3 steps (its 7 jobs stay in the file), resumed at half the factor.
  fs::copy_file(path("first.db"), path("cut.db"));
  query_rows(path("cut.db"), "DELETE FROM search_steps WHERE step >= 3; "
                             "DELETE FROM search_trials WHERE trial NOT IN (SELECT trial FROM search_steps)");
  ASSERT_EQ(query_rows(path("cut.db"), "SELECT count(*) FROM search_steps"), std::vector<std::string>{"3"});
  const SearchRunSummary resumed = run_with(path("cut.db"), 0.5);
  EXPECT_TRUE(resumed.finished);
  EXPECT_DOUBLE_EQ(resumed.spent, 7 * 8.001);
  EXPECT_EQ(query_rows(path("cut.db"), kSteps), first);
  EXPECT_EQ(query_rows(path("cut.db"), kRow), std::vector<std::string>{"8.001|2"});
  EXPECT_EQ(query_rows(path("cut.db"), "SELECT count(*), sum(attempts) FROM jobs"), std::vector<std::string>{"7|7"});
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
