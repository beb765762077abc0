// `armfarm slurm`: bad options refused, and the generated scripts executed by bash the way Slurm
// runs them (SLURM_ARRAY_TASK_ID per task, fake jobs): the shards merge into the same results as
// one run, a resubmission after a lost shard runs only what is missing, a task whose jobs failed
// still lets the merge run, and --submit calls sbatch (a stand-in on PATH) with the array id as
// the merge's afterany dependency. The scripts' text and quoting: slurm_script_test.cpp.
#include "results/results_store.hpp"
#include "runner/cli/slurm_script.hpp"
#include "support/slurm_plan.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "support/command_line.hpp"
#include "support/text_file.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm::cli {
namespace {

namespace fs = std::filesystem;

/// Runs a shell command line, stdout and stderr together.
CommandResult run_shell(const std::string& command_line) { return run_command_line(command_line); }

/// Runs armfarm_fakejobs (fake jobs); the scripts it writes run the same binary.
CommandResult run_armfarm(const std::string& arguments) { return run_shell(std::string(ARMFARM_FAKE_JOBS_BINARY) + " " + arguments); }

/// Runs task `index` (0-based) of the array script as Slurm would.
CommandResult run_array_task(const std::string& script, int index) {
  return run_shell("SLURM_ARRAY_TASK_ID=" + std::to_string(index) + " SLURM_CPUS_PER_TASK=2 bash " + script);
}


/// key -> status of every job of `sweep` in `db`.
std::map<std::string, std::string> read_statuses(const std::string& db, const std::string& sweep) {
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::map<std::string, std::string> statuses;
  for (const JobRecord& job : store.find_jobs(sweep)) statuses[job.key] = job.status;
  return statuses;
}

/// key -> that job's metric values (name, joint order).
std::map<std::string, std::vector<double>> read_metrics(const std::string& db, const std::string& sweep) {
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::map<std::string, std::vector<double>> metrics;
  for (const JobRecord& job : store.find_jobs(sweep)) {
    for (const MetricRecord& metric : store.find_metrics(job.id)) metrics[job.key].push_back(metric.value.value_or(-1.0));
  }
  return metrics;
}

class SlurmCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("slurm");
    db_ = (dir_ / "merged.db").string();
    spec_ = std::string(ARMFARM_TEST_DATA_DIR) + "/specs/fake_small.json";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::string db_;
  std::string spec_;
};

using test_support::make_plan;

// --setup: the file is sourced before armfarm runs, in both scripts, even from a hostile path.
TEST_F(SlurmCommand, SetupLinesRunBeforeArmfarm) {
  const std::string sentinel = (dir_ / "sentinel").string();
  // The script runs in dir_: a `touch sentinel` that ran would make dir_/sentinel.
  const fs::path setup = dir_ / "site's setup $(touch sentinel) `touch sentinel`.sh";
  std::ofstream(setup) << "# what a site puts here: module load gcc/12\nexport ARMFARM_SITE_MARK=loaded\n";
  const std::string stub = (dir_ / "armfarm-stub").string();
  std::ofstream(stub) << "#!/bin/sh\necho \"stub $1 saw ${ARMFARM_SITE_MARK:-nothing}\"\n";
  fs::permissions(stub, fs::perms::owner_all);
  SlurmPlan plan = make_plan();
  plan.armfarm = stub;
  plan.db = db_;
  plan.work_dir = dir_.string();
  plan.setup = setup.string();
  const std::string array = make_array_script(plan);
  EXPECT_LT(array.find("source "), array.find("set -u")) << array;
  const std::string path = (dir_ / "a.sh").string();
  std::ofstream(path) << array;
  const CommandResult task = run_shell("SLURM_ARRAY_TASK_ID=0 bash " + path);
  EXPECT_NE(task.output.find("stub run saw loaded"), std::string::npos) << task.output;
  // The merge's status line runs after the setup too (every shard marked saved first).
  for (int shard = 1; shard <= plan.tasks; ++shard) std::ofstream(make_shard_saved_path(db_, shard));
  std::ofstream(path) << make_merge_script(plan);
  const CommandResult merge = run_shell("bash " + path);
  EXPECT_NE(merge.output.find("stub merge saw loaded"), std::string::npos) << merge.output;
  EXPECT_FALSE(fs::exists(sentinel));
  // A setup that fails stops the task before armfarm.
  std::ofstream(setup) << "false\n";
  plan.setup = setup.string();
  std::ofstream(path) << make_array_script(plan);
  const CommandResult failed = run_shell("SLURM_ARRAY_TASK_ID=0 bash " + path);
  EXPECT_EQ(failed.exit_code, 2) << failed.output;
  EXPECT_EQ(failed.output.find("stub run"), std::string::npos) << failed.output;
}

TEST_F(SlurmCommand, DryRunPrintsTheScriptsAndWritesNothing) {
  const std::string setup = (dir_ / "setup.sh").string();
  std::ofstream(setup) << "module load armfarm\n";
  const CommandResult result =
      run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 2 --mem 2G --account lab --qos long --gres gpu:1 "
                  "--constraint avx2 --array-throttle 1 --job-timeout 60 --sbatch-arg=--mail-type=END "
                  "--sbatch-arg=--exclusive --setup " + setup + " --dry-run");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const std::string& expected :
       {std::string("--- ") + make_array_script_path(db_), std::string("--- ") + make_merge_script_path(db_),
        std::string("#SBATCH --array=0-1%1\n"), std::string("#SBATCH --mem='2G'\n"), std::string("#SBATCH --account='lab'\n"),
        std::string("#SBATCH --qos='long'\n"), std::string("#SBATCH --gres='gpu:1'\n"),
        std::string("#SBATCH --constraint='avx2'\n"), std::string("#SBATCH '--mail-type=END'\n"),
        std::string("#SBATCH '--exclusive'\n"), "source '" + setup + "'", std::string(" --timeout 60 --keep-failed &\n"),
        std::string("array=$(sbatch --parsable ")}) {
    EXPECT_NE(result.output.find(expected), std::string::npos) << expected << "\n" << result.output;
  }
  EXPECT_FALSE(fs::exists(make_array_script_path(db_)));
  EXPECT_FALSE(fs::exists(make_merge_script_path(db_)));
}

TEST_F(SlurmCommand, BadSiteOptionsExitTwoWithOneLine) {
  for (const std::string& options :
       {std::string("--mem 4GB"), std::string("--mem-per-cpu x"), std::string("--mem 1G --mem-per-cpu 1G"),
        std::string("--array-throttle -1"), std::string("--job-timeout -5"), std::string("--sbatch-arg=--array=0-1"),
        std::string("--sbatch-arg=exclusive"), "--setup '" + (dir_ / "no such file").string() + "'",
        std::string("--account \"$(printf 'a\\nb')\""), std::string("--gres \"$(printf 'gpu\\t1')\"")}) {
    const CommandResult result = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 2 " + options);
    EXPECT_EQ(result.exit_code, 2) << options << ": " << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << options << ": " << result.output;
    EXPECT_EQ(result.output.rfind("armfarm: --", 0), 0u) << options << ": " << result.output;
  }
  EXPECT_FALSE(fs::exists(make_array_script_path(db_)));
}

TEST_F(SlurmCommand, BadOptionsExitTwoWithOneLine) {
  for (const char* options : {"--tasks 0", "--tasks 13", "--tasks 3 --time 1:2:3:4", "--tasks 3 --partition 'a b'",
                                     "--tasks 3 --cpus-per-task 0"}) {
    const CommandResult result = run_armfarm("slurm " + spec_ + " --db " + db_ + " " + options);
    EXPECT_EQ(result.exit_code, 2) << options << ": " << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << options << ": " << result.output;
    EXPECT_EQ(result.output.rfind("armfarm: --", 0), 0u) << result.output;
  }
  const CommandResult bad_db = run_armfarm("slurm " + spec_ + " --db " + (dir_ / "no/such/r.db").string() + " --tasks 2");
  EXPECT_EQ(bad_db.exit_code, 2) << bad_db.output;
  EXPECT_NE(bad_db.output.find("its folder does not exist"), std::string::npos) << bad_db.output;
  EXPECT_FALSE(fs::exists(make_array_script_path(db_)));
}

TEST_F(SlurmCommand, ShardsRunByTheScriptsMergeToOneRunsResultsAndResumeAfterALostShard) {
  const CommandResult written = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3 --time 5");
  ASSERT_EQ(written.exit_code, 0) << written.output;
  EXPECT_NE(written.output.find("sbatch --parsable --dependency=afterany:"), std::string::npos) << written.output;
  const std::string array_script = make_array_script_path(db_);
  const std::string merge_script = make_merge_script_path(db_);
  for (int task = 0; task < 3; ++task) {
    const CommandResult result = run_array_task(array_script, task);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("shard " + std::to_string(task + 1) + "/3"), std::string::npos) << result.output;
    EXPECT_TRUE(fs::exists(make_shard_db_path(db_, task + 1)));
  }
  const CommandResult merged = run_shell("bash " + merge_script);
  ASSERT_EQ(merged.exit_code, 0) << merged.output;

  // The same spec run locally in one go gives the same jobs and numbers.
  const std::string local = (dir_ / "local.db").string();
  ASSERT_EQ(run_armfarm("run " + spec_ + " --db " + local).exit_code, 0);
  const auto statuses = read_statuses(db_, "fake_small");
  EXPECT_EQ(statuses.size(), 12u);
  for (const auto& [key, status] : statuses) EXPECT_EQ(status, "done") << key;
  EXPECT_EQ(read_metrics(db_, "fake_small"), read_metrics(local, "fake_small"));
  const CommandResult compared = run_armfarm("compare " + db_ + " " + local);
  EXPECT_EQ(compared.exit_code, 0) << compared.output;

  // Merging again changes nothing.
  const CommandResult again = run_shell("bash " + merge_script);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("0 jobs added"), std::string::npos) << again.output;
  EXPECT_EQ(again.output.find("conflict:"), std::string::npos) << again.output;

  // Everything merged: nothing to submit.
  const CommandResult complete = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3");
  EXPECT_EQ(complete.exit_code, 0) << complete.output;
  EXPECT_NE(complete.output.find("nothing to submit"), std::string::npos) << complete.output;

  // Shards done but the merged file lost: only the merge is submitted.
  fs::remove(db_);
  fs::remove(array_script);
  const CommandResult merge_only = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3");
  EXPECT_EQ(merge_only.exit_code, 0) << merge_only.output;
  EXPECT_NE(merge_only.output.find("only the merge is needed"), std::string::npos) << merge_only.output;
  EXPECT_FALSE(fs::exists(array_script));

  // A shard file lost (its task failed): the array is submitted again and only that shard runs jobs.
  const auto shard2 = read_statuses(make_shard_db_path(db_, 2), "fake_small");
  fs::remove(make_shard_db_path(db_, 2));
  const CommandResult partial = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3");
  EXPECT_NE(partial.output.find(std::to_string(12 - shard2.size()) + " finished in its 3 shard files"), std::string::npos)
      << partial.output;
  ASSERT_TRUE(fs::exists(array_script));
  EXPECT_NE(partial.output.find("resubmitting 1 of 3 shards (the others are complete): 2\n"), std::string::npos)
      << partial.output;
  EXPECT_NE(test_support::read_text_file(array_script).find("#SBATCH --array=1\n"), std::string::npos) << test_support::read_text_file(array_script);
  for (int task = 0; task < 3; ++task) {
    const CommandResult result = run_array_task(array_script, task);
    ASSERT_EQ(result.exit_code, 0) << result.output;
  }
  // Every job ran once in its shard file: the resumed shards 1 and 3 ran nothing again.
  std::size_t jobs_in_shards = 0;
  for (int shard = 1; shard <= 3; ++shard) {
    const ResultsStore store = ResultsStore::open(make_shard_db_path(db_, shard), ResultsStore::Mode::read_only);
    for (const JobRecord& job : store.find_jobs("fake_small")) {
      EXPECT_EQ(job.attempts, 1) << "shard " << shard << " job " << job.key;
      EXPECT_EQ(job.status, "done") << "shard " << shard << " job " << job.key;
      ++jobs_in_shards;
    }
  }
  EXPECT_EQ(jobs_in_shards, 12u);
  EXPECT_EQ(read_statuses(make_shard_db_path(db_, 2), "fake_small"), shard2);
  ASSERT_EQ(run_shell("bash " + merge_script).exit_code, 0);
  EXPECT_EQ(read_metrics(db_, "fake_small"), read_metrics(local, "fake_small"));
}

// `armfarm slurm` chooses the warning from the fake jobs' expected wall times (their sleep),
// calibrated by the measured ones of the database once it has finished jobs; --signal-before wins.
TEST_F(SlurmCommand, TheWarningTimeIsChosenFromTheJobCostModelUnlessGiven) {
  const std::string spec = (dir_ / "long.json").string();
  std::ofstream(spec) << R"({"name": "long", "base": {"fake": {"sleep_ms": 100000}}, "sweep": {"repeat": 2}})";
  const CommandResult chosen = run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 2 --dry-run");
  ASSERT_EQ(chosen.exit_code, 0) << chosen.output;
  // 100.01 s expected: 1.5 × 100.01 / 0.9 = 166.7.
  EXPECT_NE(chosen.output.find("warning signal 167 s before a task's time limit (from the job-cost model"), std::string::npos)
      << chosen.output;
  EXPECT_NE(chosen.output.find("#SBATCH --signal=B:USR1@167\n"), std::string::npos) << chosen.output;
  EXPECT_NE(chosen.output.find(" --stop-grace 151 "), std::string::npos) << chosen.output;
  const CommandResult limited = run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 2 --time 3 --dry-run");
  EXPECT_NE(limited.output.find("#SBATCH --signal=B:USR1@90\n"), std::string::npos) << limited.output;
  EXPECT_NE(limited.output.find("it may never finish"), std::string::npos) << limited.output;
  const CommandResult given = run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 2 --signal-before 400 --dry-run");
  EXPECT_NE(given.output.find("warning signal 400 s before a task's time limit (--signal-before"), std::string::npos)
      << given.output;
  EXPECT_NE(given.output.find(" --stop-grace 360 "), std::string::npos) << given.output;
}

// Slurm's warning before a time limit: the task script passes SIGUSR1 on, armfarm stops and
// saves what finished, the task requeues itself (scontrol, a stand-in here) without marking the
// shard saved; the requeued task resumes the shard file and no finished job runs again.
TEST_F(SlurmCommand, AWarnedTaskSavesRequeuesAndTheRequeuedTaskCompletesTheShard) {
  const std::string spec = (dir_ / "slow.json").string();
  std::ofstream(spec) << R"({"name": "slow", "base": {"fake": {"sleep_ms": 400}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60, 70, 80, 90, 100]}}})";
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const std::string log = (dir_ / "scontrol.log").string();
  std::ofstream(bin / "scontrol") << "#!/bin/sh\necho \"$*\" >> '" << log << "'\n";
  fs::permissions(bin / "scontrol", fs::perms::owner_all);
  ASSERT_EQ(run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 1").exit_code, 0);
  const std::string script = make_array_script_path(db_);
  const std::string shard = make_shard_db_path(db_, 1);
  // The warning once the shard has a finished job (`restarts`: SLURM_RESTART_COUNT).
  const auto run_warned = [&](int restarts) {
    return run_shell("PATH=" + bin.string() + ":$PATH SLURM_RESTART_COUNT=" + std::to_string(restarts) +
                     " SLURM_ARRAY_JOB_ID=77 SLURM_ARRAY_TASK_ID=0 SLURM_CPUS_PER_TASK=2 bash " + script +
                     " 2>&1 & task=$!; n=0; while [ \"$n\" -lt 600 ] && ! { [ -s '" + shard + "' ] && sqlite3 -readonly '" + shard +
                     "' \"select 1 from jobs where status='done'\" 2>/dev/null | grep -q 1; }; do sleep 0.05; n=$((n+1)); done; "
                     "kill -USR1 $task; wait $task");
  };
  // Restarted --max-requeues times already: not requeued again, the task fails.
  const CommandResult capped = run_warned(20);
  EXPECT_EQ(capped.exit_code, 75) << capped.output;
  EXPECT_NE(capped.output.find("restarted 20 times (--max-requeues 20)"), std::string::npos) << capped.output;
  EXPECT_FALSE(fs::exists(log));
  fs::remove(shard);
  const CommandResult warned = run_warned(0);
  EXPECT_EQ(warned.exit_code, 0) << warned.output;
  EXPECT_NE(warned.output.find("stopped by Slurm's warning signal"), std::string::npos) << warned.output;
  EXPECT_NE(warned.output.find("shard 1/1 requeued"), std::string::npos) << warned.output;
  EXPECT_EQ(test_support::read_text_file(log), "requeue 77_0\n");
  EXPECT_FALSE(fs::exists(make_shard_saved_path(db_, 1)));
  std::map<std::string, std::string> first = read_statuses(shard, "slow");
  int done_first = 0;
  for (const auto& [key, status] : first) done_first += status == "done";
  EXPECT_GE(done_first, 1);
  EXPECT_LT(done_first, 10) << warned.output;
  // The requeued task.
  const CommandResult resumed = run_array_task(script, 0);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find(std::to_string(done_first) + " already done (skipped)"), std::string::npos) << resumed.output;
  EXPECT_TRUE(fs::exists(make_shard_saved_path(db_, 1)));
  const ResultsStore store = ResultsStore::open(shard, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs("slow");
  EXPECT_EQ(jobs.size(), 10u);
  for (const JobRecord& job : jobs) {
    EXPECT_EQ(job.status, "done") << job.key;
    if (first.at(job.key) == "done") {
      EXPECT_EQ(job.attempts, 1) << job.key << ": a finished job ran again";
    }
  }
}

// Issue 29: a shard that never ran does not hold back the others. The merge brings in what is
// there and names the missing shard; `armfarm slurm` again submits only that shard.
TEST_F(SlurmCommand, APartialMergeNamesTheMissingShardAndTheResubmissionRunsOnlyIt) {
  ASSERT_EQ(run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3").exit_code, 0);
  const std::string array_script = make_array_script_path(db_);
  const std::string merge_script = make_merge_script_path(db_);
  ASSERT_EQ(run_array_task(array_script, 0).exit_code, 0);
  ASSERT_EQ(run_array_task(array_script, 2).exit_code, 0);
  const CommandResult merged = run_shell("bash " + merge_script);
  EXPECT_EQ(merged.exit_code, 1) << merged.output;
  EXPECT_NE(merged.output.find("merged 2 of 3 shards; 1 did not save their results (shard 2;"), std::string::npos)
      << merged.output;
  const std::size_t in_1_and_3 = read_statuses(make_shard_db_path(db_, 1), "fake_small").size() +
                                 read_statuses(make_shard_db_path(db_, 3), "fake_small").size();
  EXPECT_EQ(read_statuses(db_, "fake_small").size(), in_1_and_3);
  EXPECT_LT(in_1_and_3, 12u);
  // The merge names the missing jobs, each of shard 2, and only those.
  const std::string missing_count = std::to_string(in_1_and_3) + " of 12 jobs of sweep fake_small finished in " + db_ + "; " +
                                    std::to_string(12 - in_1_and_3) + " missing, in shard 2 of 3:\n";
  EXPECT_NE(merged.output.find(missing_count), std::string::npos) << merged.output;
  const std::map<std::string, std::string> merged_statuses = read_statuses(db_, "fake_small");
  std::size_t named = 0;
  for (std::size_t at = merged.output.find("\n  shard "); at != std::string::npos; at = merged.output.find("\n  shard ", at + 1)) {
    EXPECT_EQ(merged.output.compare(at, 12, "\n  shard 2: "), 0) << merged.output;
    const std::string label = merged.output.substr(at + 12, 8);  // the key's first 8 digits
    for (const auto& [key, status] : merged_statuses) EXPECT_NE(key.substr(0, 8), label) << "a merged job named missing";
    ++named;
  }
  EXPECT_EQ(named, 12 - in_1_and_3) << merged.output;
  const CommandResult again = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3");
  EXPECT_NE(again.output.find("resubmitting 1 of 3 shards (the others are complete): 2\n"), std::string::npos) << again.output;
  EXPECT_NE(test_support::read_text_file(array_script).find("#SBATCH --array=1\n"), std::string::npos) << test_support::read_text_file(array_script);
  ASSERT_EQ(run_array_task(array_script, 1).exit_code, 0);
  const CommandResult complete = run_shell("bash " + merge_script);
  EXPECT_EQ(complete.exit_code, 0) << complete.output;
  const CommandResult none = run_armfarm("slurm " + spec_ + " --db " + db_ + " --tasks 3 --missing");
  EXPECT_EQ(none.exit_code, 0) << none.output;
  EXPECT_NE(none.output.find("12 of 12 jobs of sweep fake_small finished in " + db_ + "; none missing\n"), std::string::npos)
      << none.output;
  const auto statuses = read_statuses(db_, "fake_small");
  EXPECT_EQ(statuses.size(), 12u);
  for (const auto& [key, status] : statuses) EXPECT_EQ(status, "done") << key;
}

// Issue 30, case 4: a sweep named "x\nrm -rf DIR\n#" put a bare `rm -rf DIR` line above the
// #SBATCH lines. Now the name stays in its comment line (control characters replaced), so the
// only lines that run are ours; bash parses both scripts and the DIR survives running them.
TEST_F(SlurmCommand, AHostileSweepNameNeverLeavesItsCommentLine) {
  const fs::path victim = dir_ / "DIR";
  fs::create_directories(victim);
  const std::string sentinel = (dir_ / "sentinel").string();
  SlurmPlan plan = make_plan();
  plan.sweep = "x\nrm -rf " + victim.string() + "\n#`touch " + sentinel + "`$(touch " + sentinel + ")'\"\x1b[31m";
  plan.db = db_;
  plan.armfarm = "/bin/true";
  plan.work_dir = dir_.string();
  for (const std::string& script : {make_array_script(plan), make_merge_script(plan)}) {
    std::istringstream lines(script);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.find("rm -rf") != std::string::npos) {
        EXPECT_EQ(line.rfind("# ", 0), 0u) << line;
      }
      EXPECT_EQ(line.find('\x1b'), std::string::npos) << line;
    }
    const std::string path = (dir_ / "s.sh").string();
    std::ofstream(path) << script;
    EXPECT_EQ(run_shell("bash -n " + path).exit_code, 0) << script;
    run_shell("SLURM_ARRAY_TASK_ID=0 bash " + path);
  }
  EXPECT_TRUE(fs::exists(victim));
  EXPECT_FALSE(fs::exists(sentinel));
}

// Issue 30, case 5 (Slurm half): a shard whose database filled up exited 0 through the script
// and the merge ran on what was there. Now the task fails with armfarm's exit 3, the shard is
// not marked saved, and the merge names it instead of merging.
TEST_F(SlurmCommand, AShardOnAFullDiskFailsItsTaskAndTheMergeNamesIt) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  const fs::path disk = dir_ / "disk";
  fs::create_directories(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=384k") != 0) GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    std::string where;
    ~Unmount() { umount2(where.c_str(), MNT_DETACH); }
  } unmount{disk.string()};
  const std::string spec = (dir_ / "full.json").string();
  std::ofstream(spec) << R"({"name": "full", "base": {"fake": {"sleep_ms": 5}, "simulation": {"samples": 2000}},
      "sweep": {"grid": {"learning.lwpr.init_D": [10, 20, 30, 40, 50, 60, 70, 80, 90, 100]}, "repeat": 3}})";
  const std::string db = (disk / "full.db").string();
  ASSERT_EQ(run_armfarm("slurm " + spec + " --db " + db + " --tasks 1").exit_code, 0);
  // The one shard fills the disk.
  const CommandResult task = run_array_task(make_array_script_path(db), 0);
  EXPECT_EQ(task.exit_code, 3) << task.output;
  EXPECT_NE(task.output.find("not marked saved, the merge leaves it out"), std::string::npos) << task.output;
  EXPECT_FALSE(fs::exists(make_shard_saved_path(db, 1)));
  const CommandResult merged = run_shell("bash " + make_merge_script_path(db));
  EXPECT_EQ(merged.exit_code, 1) << merged.output;
  EXPECT_NE(merged.output.find("merged 0 of 1 shards; 1 did not save their results (shard 1;"), std::string::npos)
      << merged.output;
  EXPECT_FALSE(fs::exists(db));
}

TEST_F(SlurmCommand, TaskWithFailedJobsSucceedsSoTheMergeBringsThemIn) {
  const std::string spec = (dir_ / "failing.json").string();
  std::ofstream(spec) << R"({"name": "failing", "base": {"fake": {"sleep_ms": 0}},
    "sweep": {"grid": {"fake.fail": [false, true], "control.gain_scale": [0.5, 1.0]}}})";
  ASSERT_EQ(run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 1").exit_code, 0);
  const CommandResult task = run_array_task(make_array_script_path(db_), 0);
  EXPECT_EQ(task.exit_code, 0) << task.output;
  EXPECT_NE(task.output.find("recorded failed, diverged or timed-out jobs"), std::string::npos) << task.output;
  const CommandResult merged = run_shell("bash " + make_merge_script_path(db_));
  EXPECT_EQ(merged.exit_code, 0) << merged.output;
  std::map<std::string, int> counts;
  for (const auto& [key, status] : read_statuses(db_, "failing")) ++counts[status];
  EXPECT_EQ(counts["done"], 2);
  EXPECT_EQ(counts["failed"], 2);
  // Failures are results (issue 29): the task run again runs nothing, and `armfarm slurm` finds
  // nothing to submit; only --retry-failed runs the failed jobs again.
  const CommandResult again = run_array_task(make_array_script_path(db_), 0);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("0 done, 0 failed, 0 diverged, 0 timed out, 4 already done (skipped)"), std::string::npos)
      << again.output;
  const CommandResult resubmitted = run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 1");
  EXPECT_NE(resubmitted.output.find("nothing to submit"), std::string::npos) << resubmitted.output;
  const CommandResult retry = run_armfarm("slurm " + spec + " --db " + db_ + " --tasks 1 --retry-failed");
  EXPECT_NE(retry.output.find("2 finished in"), std::string::npos) << retry.output;
  EXPECT_EQ(test_support::read_text_file(make_array_script_path(db_)).find("--keep-failed"), std::string::npos);
  const CommandResult retried = run_array_task(make_array_script_path(db_), 0);
  EXPECT_NE(retried.output.find("0 done, 2 failed, 0 diverged, 0 timed out, 2 already done (skipped)"), std::string::npos)
      << retried.output;
  // A bad spec (exit 2) fails the task.
  std::ofstream(spec) << "{";
  EXPECT_EQ(run_array_task(make_array_script_path(db_), 0).exit_code, 2);
}

TEST_F(SlurmCommand, SubmitPassesTheArrayIdToTheMergeDependency) {
  // A stand-in sbatch: logs its arguments, prints ids the way --parsable does (with a cluster name).
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const std::string log = (dir_ / "sbatch.log").string();
  std::ofstream(bin / "sbatch") << "#!/bin/sh\necho \"$*\" >> '" << log
                                << "'\nn=$(wc -l < '" << log << "')\necho \"$((4240 + n));cluster1\"\n";
  fs::permissions(bin / "sbatch", fs::perms::owner_all);
  const CommandResult result =
      run_shell("PATH=" + bin.string() + ":$PATH " + ARMFARM_FAKE_JOBS_BINARY + " slurm " + spec_ + " --db " + db_ + " --tasks 2 --submit");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("submitted array job 4241 (2 tasks)"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("submitted merge job 4242 (after array job 4241 ends)"), std::string::npos)
      << result.output;
  const std::string calls = test_support::read_text_file(log);
  EXPECT_EQ(calls, "--parsable " + make_array_script_path(db_) + "\n--parsable --dependency=afterany:4241 " +
                       make_merge_script_path(db_) + "\n");

  // sbatch failing: exit 2 with one line.
  std::ofstream(bin / "sbatch") << "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n";
  const CommandResult failed =
      run_shell("PATH=" + bin.string() + ":$PATH " + ARMFARM_FAKE_JOBS_BINARY + " slurm " + spec_ + " --db " + db_ + " --tasks 2 --submit");
  EXPECT_EQ(failed.exit_code, 2) << failed.output;
  EXPECT_NE(failed.output.find("armfarm: sbatch for the job array failed (exit 1)"), std::string::npos) << failed.output;
}

}  // namespace
}  // namespace armfarm::cli
