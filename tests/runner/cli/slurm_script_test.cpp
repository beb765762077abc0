// The generated sbatch scripts as text: what each directive and line holds, time limits in
// every sbatch form, site options quoted so that sbatch reads each as one argument, the warning
// signal before the time limit. The scripts run by bash: tests/runner/cli/cmd_slurm_test.cpp.
#include "runner/cli/slurm_script.hpp"
#include "support/slurm_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace armfarm::cli {
namespace {

using test_support::make_plan;

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
  EXPECT_NE(script.find("for shard in $(seq 1 4); do\n"), std::string::npos) << script;
  EXPECT_NE(script.find(" merge \"$db\" \"${saved[@]}\" || exit $?\n"), std::string::npos) << script;
  const std::vector<std::string> commands = make_submit_commands(plan);
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0], "array=$(sbatch --parsable '/scratch/me/results.db.array.sbatch')");
  EXPECT_EQ(commands[1], "sbatch --parsable --dependency=afterany:${array%%;*} '/scratch/me/results.db.merge.sbatch'");
  // A resubmission of some shards lists their task indices (shard - 1) as ranges.
  SlurmPlan some = plan;
  some.tasks = 9;
  some.shards = {2, 9, 3, 4, 7};
  EXPECT_NE(make_array_script(some).find("#SBATCH --array=1-3,6,8\n"), std::string::npos) << make_array_script(some);
  some.array_throttle = 2;
  EXPECT_NE(make_array_script(some).find("#SBATCH --array=1-3,6,8%2\n"), std::string::npos);
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

/// The arguments of an #SBATCH line split as sbatch splits them (a second reading, written from
/// sbatch's documented rule: white space separates, '...' and "..." group, a backslash takes the
/// next character as it is, also inside quotes; an unquoted # starts a comment).
std::vector<std::string> split_sbatch_line(const std::string& line) {
  EXPECT_EQ(line.rfind("#SBATCH ", 0), 0u) << line;
  std::vector<std::string> arguments;
  std::string current;
  bool in_argument = false, escaped = false;
  char quote = 0;
  for (std::size_t i = 8; i < line.size(); ++i) {
    const char c = line[i];
    if (escaped) {
      current += c;
      escaped = false;
    } else if (c == '\\') {
      escaped = in_argument = true;
    } else if (quote != 0) {
      if (c == quote) quote = 0; else current += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_argument = true;
    } else if (c == ' ' || c == '\t') {
      if (in_argument) arguments.push_back(current);
      current.clear();
      in_argument = false;
    } else if (c == '#') {
      break;
    } else {
      current += c;
      in_argument = true;
    }
  }
  if (in_argument) arguments.push_back(current);
  return arguments;
}

/// Every #SBATCH line of `script` as sbatch reads it, in order (it stops at the first command).
std::vector<std::string> read_sbatch_arguments(const std::string& script) {
  std::vector<std::string> arguments;
  std::istringstream lines(script);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("#SBATCH ", 0) == 0) {
      for (const std::string& argument : split_sbatch_line(line)) arguments.push_back(argument);
    } else if (!line.empty() && line[0] != '#') {
      break;
    }
  }
  return arguments;
}

bool contains(const std::vector<std::string>& items, const std::string& item) {
  return std::find(items.begin(), items.end(), item) != items.end();
}

TEST(SlurmScript, EachSiteOptionReachesItsDirective) {
  SlurmPlan plan = make_plan();
  plan.mem = "4G";
  plan.account = "proj-123";
  plan.qos = "normal";
  plan.gres = "gpu:a100:1";
  plan.constraint = "skylake&ib";
  plan.array_throttle = 2;
  plan.job_timeout = 90.5;
  plan.sbatch_args = {"--mail-type=END,FAIL", "--exclusive"};
  const std::string array = make_array_script(plan);
  const std::string merge = make_merge_script(plan);
  EXPECT_NE(array.find("#SBATCH --mem='4G'\n"), std::string::npos) << array;
  EXPECT_NE(array.find("#SBATCH --array=0-3%2\n"), std::string::npos) << array;
  EXPECT_NE(array.find(" -j \"${SLURM_CPUS_PER_TASK:-3}\" --stop-grace 270 --timeout 90.5 --keep-failed &\n"), std::string::npos) << array;
  const std::vector<std::string> array_arguments = read_sbatch_arguments(array);
  const std::vector<std::string> merge_arguments = read_sbatch_arguments(merge);
  for (const char* both : {"--mem=4G", "--account=proj-123", "--qos=normal", "--mail-type=END,FAIL", "--exclusive"}) {
    EXPECT_TRUE(contains(array_arguments, both)) << both << "\n" << array;
    EXPECT_TRUE(contains(merge_arguments, both)) << both << "\n" << merge;
  }
  // The merge needs no GPU or node feature, and runs once.
  for (const char* array_only : {"--gres=gpu:a100:1", "--constraint=skylake&ib", "--array=0-3%2"}) {
    EXPECT_TRUE(contains(array_arguments, array_only)) << array_only << "\n" << array;
    EXPECT_FALSE(contains(merge_arguments, array_only)) << array_only << "\n" << merge;
  }
  EXPECT_EQ(merge.find("--timeout"), std::string::npos);
  plan.mem.clear();
  plan.mem_per_cpu = "1500M";
  EXPECT_TRUE(contains(read_sbatch_arguments(make_array_script(plan)), "--mem-per-cpu=1500M"));
  // Unset options write no line.
  const std::string plain = make_array_script(make_plan());
  for (const char* absent : {"--mem", "--account", "--qos", "--gres", "--constraint", "%", "--timeout", "source "}) {
    EXPECT_EQ(plain.find(std::string("#SBATCH ") + absent), std::string::npos) << absent;
  }
  EXPECT_EQ(plain.find("source "), std::string::npos);
  EXPECT_EQ(plain.find("--timeout"), std::string::npos);
}

TEST(SlurmScript, HostileOptionValuesStayOneArgument) {
  SlurmPlan plan = make_plan();
  const std::string hostile = "x' --wrap='touch /tmp/owned' \"$(id)\" \\ # `id`";
  plan.account = hostile;
  plan.qos = hostile;
  plan.gres = hostile;
  plan.constraint = hostile;
  plan.sbatch_args = {"--comment=" + hostile};
  for (const std::string& script : {make_array_script(plan), make_merge_script(plan)}) {
    const std::vector<std::string> arguments = read_sbatch_arguments(script);
    EXPECT_TRUE(contains(arguments, "--account=" + hostile)) << script;
    EXPECT_TRUE(contains(arguments, "--qos=" + hostile)) << script;
    EXPECT_TRUE(contains(arguments, "--comment=" + hostile)) << script;
    for (const std::string& argument : arguments) EXPECT_NE(argument.rfind("--wrap", 0), 0u) << argument;
  }
  EXPECT_TRUE(contains(read_sbatch_arguments(make_array_script(plan)), "--gres=" + hostile));
  EXPECT_EQ(make_sbatch_quoted("--qos", "it's a\\b"), "'it\\'s a\\\\b'");
  for (const char* bad : {"a\nb", "a\rb", "a\tb", "\x1b[31m"}) {
    EXPECT_THROW(make_sbatch_quoted("--account", bad), std::invalid_argument) << bad;
  }
  for (const char* good : {"0", "4000", "500M", "4G", "1t", "16g"}) EXPECT_NO_THROW(check_slurm_memory("--mem", good)) << good;
  for (const char* bad : {"", "G", "4GB", "4.5G", "-1", "4 G", "4G;id"}) {
    EXPECT_THROW(check_slurm_memory("--mem", bad), std::invalid_argument) << bad;
  }
  for (const char* good : {"--exclusive", "--mail-type=END", "-N1", "--comment=a b"}) EXPECT_NO_THROW(check_sbatch_arg(good)) << good;
  for (const char* bad : {"", "-", "exclusive", "--array=0-9", "--dependency=afterok:1", "--output=x", "-J", "-oX",
                          "--job-name=y", "--comment=a\nid"}) {
    EXPECT_THROW(check_sbatch_arg(bad), std::invalid_argument) << bad;
  }
}

TEST(SlurmScript, WarningSignalAndRequeue) {
  SlurmPlan plan = make_plan();
  const std::string array = make_array_script(plan);
  EXPECT_NE(array.find("#SBATCH --signal=B:USR1@300\n#SBATCH --requeue\n#SBATCH --open-mode=append\n"), std::string::npos) << array;
  EXPECT_NE(array.find("scontrol requeue \"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\""), std::string::npos);
  EXPECT_NE(array.find("if [ \"${SLURM_RESTART_COUNT:-0}\" -lt 20 ]; then\n"), std::string::npos) << array;
  plan.max_requeues = 3;
  EXPECT_NE(make_array_script(plan).find("if [ \"${SLURM_RESTART_COUNT:-0}\" -lt 3 ]; then\n"), std::string::npos);
  EXPECT_EQ(make_merge_script(plan).find("--signal"), std::string::npos);
  plan.signal_before = 45;
  plan.requeue = false;
  const std::string no_requeue = make_array_script(plan);
  EXPECT_NE(no_requeue.find("#SBATCH --signal=B:USR1@45\n"), std::string::npos);
  EXPECT_EQ(no_requeue.find("requeue"), no_requeue.find("requeued")) << no_requeue;  // only in the message
  EXPECT_EQ(no_requeue.find("--requeue"), std::string::npos);
  EXPECT_EQ(no_requeue.find("scontrol"), std::string::npos);
}

TEST(SlurmScript, TimeLimitSecondsInEachSbatchForm) {
  EXPECT_EQ(calc_slurm_time_seconds("90"), 90 * 60);
  EXPECT_EQ(calc_slurm_time_seconds("3:30"), 3 * 60 + 30);
  EXPECT_EQ(calc_slurm_time_seconds("2:00:05"), 2 * 3600 + 5);
  EXPECT_EQ(calc_slurm_time_seconds("1-12"), 86400 + 12 * 3600);
  EXPECT_EQ(calc_slurm_time_seconds("1-2:03"), 86400 + 2 * 3600 + 3 * 60);
  EXPECT_EQ(calc_slurm_time_seconds("2-0:0:7"), 2 * 86400 + 7);
  EXPECT_EQ(calc_slurm_time_seconds("UNLIMITED"), std::nullopt);
}

// The warning time leaves the longest job 1.5 times its expected wall time once the reserve
// (calc_stop_grace) is taken off, at least 60 s, at most half the time limit.
TEST(SlurmScript, TheWarningTimeComesFromTheLongestJob) {
  EXPECT_EQ(choose_signal_before({1.0, 10.0, 3.0}, ""), 60);  // 1.5 × 10 + 5 = 20: the floor of 60 s
  EXPECT_EQ(choose_signal_before({100.0}, ""), 167);          // 150 / 0.9 = 166.7
  EXPECT_GE(calc_stop_grace(167), 150);
  EXPECT_EQ(choose_signal_before({100.0}, "5"), 150);         // half of 300 s
  EXPECT_EQ(choose_signal_before({10.0}, "1"), 30);
  EXPECT_EQ(choose_signal_before({1e6}, ""), 65535);
  EXPECT_EQ(choose_signal_before({}, "infinite"), 60);
  for (const double longest : {0.5, 20.0, 30.0, 40.0, 1000.0}) {
    const int chosen = choose_signal_before({longest}, "");
    EXPECT_GE(calc_stop_grace(chosen), 1.5 * longest) << longest;
  }
  EXPECT_EQ(calc_stop_grace(60), 54);
  EXPECT_EQ(calc_stop_grace(300), 270);
  EXPECT_EQ(calc_stop_grace(30), 25);
  EXPECT_EQ(calc_stop_grace(3), 0);
  SlurmPlan plan = make_plan();
  plan.signal_before = 60;
  const std::string array = make_array_script(plan);
  EXPECT_NE(array.find("#SBATCH --signal=B:USR1@60\n"), std::string::npos) << array;
  EXPECT_NE(array.find(" --stop-grace 54 "), std::string::npos) << array;
}

}  // namespace
}  // namespace armfarm::cli
