// `armfarm slurm`: the generated sbatch scripts (text, quoting, validation), and the scripts
// executed by bash the way Slurm runs them (SLURM_ARRAY_TASK_ID per task, fake jobs): the
// shards merge into the same results as one run, a resubmission after a lost shard runs only
// what is missing, a task whose jobs failed still lets the merge run, and --submit calls sbatch
// (a stand-in on PATH) with the array id as the merge's afterok dependency.
#include "results/results_store.hpp"
#include "runner/cli/slurm_script.hpp"

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

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm::cli {
namespace {

namespace fs = std::filesystem;

/// Runs a shell command line (fake jobs), stdout and stderr together.
CommandResult run_shell(const std::string& command_line) {
  const std::string command = "ARMFARM_FAKE_JOBS=1 " + command_line;
  return run_command_line(command);
}

CommandResult run_armfarm(const std::string& arguments) { return run_shell(std::string(ARMFARM_BINARY) + " " + arguments); }

/// Runs task `index` (0-based) of the array script as Slurm would.
CommandResult run_array_task(const std::string& script, int index) {
  return run_shell("SLURM_ARRAY_TASK_ID=" + std::to_string(index) + " SLURM_CPUS_PER_TASK=2 bash " + script);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
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

SlurmPlan make_plan() {
  SlurmPlan plan;
  plan.armfarm = "/opt/armfarm/bin/armfarm";
  plan.spec = "/home/me/sweeps/it's here.json";
  plan.db = "/scratch/me/results.db";
  plan.work_dir = "/home/me";
  plan.sweep = "quick start";
  plan.jobs = 12;
  plan.tasks = 4;
  plan.cpus_per_task = 3;
  return plan;
}

TEST(SlurmScript, ArrayScriptRunsShardIOfNIntoItsOwnFile) {
  const std::string script = make_array_script(make_plan());
  EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_NE(script.find("#SBATCH --array=0-3\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --cpus-per-task=3\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --job-name=armfarm-quick_start\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --output=/scratch/me/results.db.slurm-%A_%a.log\n"), std::string::npos);
  EXPECT_NE(script.find("shard=$((SLURM_ARRAY_TASK_ID + 1))\n"), std::string::npos);
  EXPECT_NE(script.find("db='/scratch/me/results.db'.shard-\"$shard\".db\n"), std::string::npos);
  EXPECT_NE(script.find("'/opt/armfarm/bin/armfarm' run '/home/me/sweeps/it'\\''s here.json' --shard \"$shard/$count\""),
            std::string::npos)
      << script;
  EXPECT_NE(script.find("count=4\n"), std::string::npos);
  EXPECT_NE(script.find("cd '/home/me' || exit 2\n"), std::string::npos);
  // No time limit or partition unless asked.
  EXPECT_EQ(script.find("--time"), std::string::npos);
  EXPECT_EQ(script.find("--partition"), std::string::npos);
}

TEST(SlurmScript, TimeAndPartitionGoToBothScripts) {
  SlurmPlan plan = make_plan();
  plan.time_limit = "1-02:30:00";
  plan.partition = "short,long";
  for (const std::string& script : {make_array_script(plan), make_merge_script(plan)}) {
    EXPECT_NE(script.find("#SBATCH --time=1-02:30:00\n"), std::string::npos) << script;
    EXPECT_NE(script.find("#SBATCH --partition=short,long\n"), std::string::npos) << script;
  }
}

TEST(SlurmScript, MergeScriptMergesEveryShardAfterTheArray) {
  const SlurmPlan plan = make_plan();
  const std::string script = make_merge_script(plan);
  EXPECT_NE(script.find("#SBATCH --kill-on-invalid-dep=yes\n"), std::string::npos);
  EXPECT_NE(script.find("merge \"$db\" \"$db.shard-1.db\" \"$db.shard-2.db\" \"$db.shard-3.db\" \"$db.shard-4.db\" || exit $?\n"),
            std::string::npos)
      << script;
  EXPECT_EQ(script.find("shard-5"), std::string::npos);
  const std::vector<std::string> commands = make_submit_commands(plan);
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0], "array=$(sbatch --parsable '/scratch/me/results.db.array.sbatch')");
  EXPECT_EQ(commands[1], "sbatch --parsable --dependency=afterok:${array%%;*} '/scratch/me/results.db.merge.sbatch'");
  EXPECT_EQ(make_shard_db_path("/a/r.db", 7), "/a/r.db.shard-7.db");
}

TEST(SlurmScript, TimeLimitsInSbatchForms) {
  for (const char* good : {"0", "90", "30:00", "2:00:00", "1-0", "1-12", "2-12:30", "7-23:59:59", "INFINITE", "unlimited"}) {
    EXPECT_NO_THROW(check_slurm_time_limit(good)) << good;
  }
  for (const char* bad : {"", "1h", "1:2:3:4", "10:60", "1:60:00", "1-24", "1-1:60", "-5", "1-", ":30", "1.5", "1 0"}) {
    EXPECT_THROW(check_slurm_time_limit(bad), std::invalid_argument) << bad;
  }
  EXPECT_NO_THROW(check_slurm_partition("gpu_a100,cpu-long.x"));
  for (const char* bad : {"a b", "a,,b", "a;rm", ""}) EXPECT_THROW(check_slurm_partition(bad), std::invalid_argument) << bad;
  EXPECT_NO_THROW(check_slurm_db_path("/scratch/me/r-1.db"));
  for (const char* bad : {"/a b/r.db", "/a/r%j.db", "/a/'r.db", "/a/r\n.db"}) {
    EXPECT_THROW(check_slurm_db_path(bad), std::invalid_argument) << bad;
  }
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
  EXPECT_NE(written.output.find("sbatch --parsable --dependency=afterok:"), std::string::npos) << written.output;
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
  EXPECT_NE(partial.output.find(std::to_string(12 - shard2.size()) + " done in its 3 shard files"), std::string::npos)
      << partial.output;
  ASSERT_TRUE(fs::exists(array_script));
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
  EXPECT_NE(task.output.find("not marked saved, the merge will not run"), std::string::npos) << task.output;
  EXPECT_FALSE(fs::exists(make_shard_saved_path(db, 1)));
  const CommandResult merged = run_shell("bash " + make_merge_script_path(db));
  EXPECT_EQ(merged.exit_code, 1) << merged.output;
  EXPECT_NE(merged.output.find("not merging: 1 of 1 shards did not save their results (shard 1)"), std::string::npos)
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
      run_shell("PATH=" + bin.string() + ":$PATH " + ARMFARM_BINARY + " slurm " + spec_ + " --db " + db_ + " --tasks 2 --submit");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("submitted array job 4241 (2 tasks)"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("submitted merge job 4242 (after array job 4241 succeeds)"), std::string::npos)
      << result.output;
  const std::string calls = read_text(log);
  EXPECT_EQ(calls, "--parsable " + make_array_script_path(db_) + "\n--parsable --dependency=afterok:4241 " +
                       make_merge_script_path(db_) + "\n");

  // sbatch failing: exit 2 with one line.
  std::ofstream(bin / "sbatch") << "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n";
  const CommandResult failed =
      run_shell("PATH=" + bin.string() + ":$PATH " + ARMFARM_BINARY + " slurm " + spec_ + " --db " + db_ + " --tasks 2 --submit");
  EXPECT_EQ(failed.exit_code, 2) << failed.output;
  EXPECT_NE(failed.output.find("armfarm: sbatch for the job array failed (exit 1)"), std::string::npos) << failed.output;
}

}  // namespace
}  // namespace armfarm::cli
