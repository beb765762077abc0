// `armfarm slurm SPEC --db DB --tasks N`: writes the sbatch scripts that run a sweep on a Slurm
// cluster as a job array of N shards, each into its own database file beside DB (one writer per
// SQLite file, never one file shared over a network filesystem), plus a merge job after the
// array; prints the commands that submit them, or with --submit submits them. Run again after
// a partial failure it submits only what is missing (done shards resume as no-ops).
#include "analysis/printable_text.hpp"
#include "results/results_store.hpp"
#include "runner/cli/slurm_script.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/job_cost.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/execution/progress_reporter.hpp"
#include "runner/execution/shard.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>

namespace armfarm::cli {

namespace {

namespace fs = std::filesystem;

/// How many of `keys` are finished in the database at `path` (0 when there is no such file):
/// done, and unless `retry_failed` also failed, diverged or timed out (those are results).
int count_done_jobs(const std::string& path, const std::vector<std::string>& keys, bool retry_failed,
                    std::set<std::string>& done) {
  if (!fs::exists(path)) return 0;
  const ResultsStore store = ResultsStore::open(path, ResultsStore::Mode::read_only);
  int count = 0;
  for (const std::string& key : keys) {
    const std::optional<JobRecord> job = store.find_job(key);
    const bool finished = job && (job->status == "done" || (!retry_failed && (job->status == "failed" || job->status == "diverged" ||
                                                                           job->status == "timeout")));
    if (finished) {
      ++count;
      done.insert(key);
    }
  }
  return count;
}

/// Whether shard `shard`'s task has nothing left to do: its results are marked saved and every
/// job its file registered is finished (done, or a kept failure unless `retry_failed`).
bool is_shard_complete(const std::string& db, int shard, const std::string& sweep, bool retry_failed) {
  const std::string path = make_shard_db_path(db, shard);
  if (!fs::exists(make_shard_saved_path(db, shard)) || !fs::exists(path)) return false;
  const ResultsStore store = ResultsStore::open(path, ResultsStore::Mode::read_only);
  const std::vector<JobRecord> jobs = store.find_jobs(sweep);
  if (jobs.empty()) return false;
  for (const JobRecord& job : jobs) {
    const bool kept = !retry_failed && (job.status == "failed" || job.status == "diverged" || job.status == "timeout");
    if (job.status != "done" && !kept) return false;
  }
  return true;
}

/// Writes `text` to `path` whole or not at all (a temporary file renamed over it).
void write_script(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(temporary + ": cannot write");
  }
  fs::permissions(temporary, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                 fs::perms::others_read | fs::perms::others_exec);
  fs::rename(temporary, path);
}

/// Runs a submit command through the shell; returns the job id sbatch --parsable printed
/// ("id" or "id;cluster" → "id"). Throws with `what` on failure.
std::string run_sbatch(const std::string& command, const std::string& what) {
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot start sbatch for the " + what);
  std::string output;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  std::string id = output.substr(0, output.find_first_of(";\n"));
  if (code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    throw std::runtime_error("sbatch for the " + what + " failed (exit " + std::to_string(code) +
                             (code == 127 ? ", sbatch not found: is this a Slurm submit host?" : "") + ")");
  }
  return id;
}

/// The jobs of `sweep` not in `finished`, each with its shard of plan.tasks (dealt as the tasks'
/// `armfarm run --shard` deals them), at most 10 lines and "... and N more".
void print_missing_jobs(const ExpandedSweep& sweep, const SlurmPlan& plan, const std::set<std::string>& finished) {
  std::vector<std::string> keys;
  for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
  const JobKind kind = make_job_kind_from_environment();
  const std::vector<int> shard_of = calc_shard_assignment(keys, calc_job_costs(sweep, kind.estimate_cost), plan.tasks);
  std::set<int> shards;
  std::vector<std::size_t> missing;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (finished.count(keys[i]) > 0) continue;
    missing.push_back(i);
    shards.insert(shard_of[i]);
  }
  std::cout << "armfarm slurm: " << keys.size() - missing.size() << " of " << keys.size() << " jobs of sweep "
            << make_printable_text(plan.sweep) << " finished in " << plan.db;
  if (missing.empty()) {
    std::cout << "; none missing\n";
    return;
  }
  std::cout << "; " << missing.size() << " missing, in shard" << (shards.size() == 1 ? "" : "s");
  for (const int shard : shards) std::cout << " " << shard;
  std::cout << " of " << plan.tasks << ":\n";
  const std::size_t shown = std::min<std::size_t>(missing.size(), 10);
  for (std::size_t i = 0; i < shown; ++i) {
    std::cout << "  shard " << shard_of[missing[i]] << ": " << make_printable_text(make_job_label(sweep.jobs[missing[i]])) << "\n";
  }
  if (missing.size() > shown) std::cout << "  ... and " << missing.size() - shown << " more\n";
}

struct SlurmOptions {
  std::string spec;
  std::string db;
  int tasks = 0;
  std::string time_limit;
  std::string partition;
  int cpus_per_task = 1;
  bool submit = false;
  std::string mem, mem_per_cpu, account, qos, gres, constraint;
  int array_throttle = 0;
  double job_timeout = 0.0;
  std::vector<std::string> sbatch_args;
  std::string setup;
  bool dry_run = false;
  bool missing = false;
  bool retry_failed = false;
  int signal_before = 0;  // 0: from the job-cost model (choose_signal_before)
  bool requeue = SlurmPlan{}.requeue;
  int max_requeues = SlurmPlan{}.max_requeues;
};

void add_slurm_options(CLI::App& app, SlurmOptions& options) {
  app.add_option("spec", options.spec, "Sweep spec (JSON)")->required();
  app.add_option("--db", options.db, "Merged results database; shard files <DB>.shard-I.db, scripts and logs beside it")
      ->required();
  app.add_option("--tasks", options.tasks, "Array tasks = shards of the sweep (1 to the number of jobs)")->required();
  app.add_option("--time", options.time_limit, "Time limit of each task and of the merge, sbatch's form (e.g. 2:00:00)");
  app.add_option("--partition", options.partition, "Slurm partition (default: the cluster's default)");
  app.add_option("--cpus-per-task", options.cpus_per_task, "CPUs per task; each task runs that many jobs at once")
      ->capture_default_str();
  app.add_flag("--submit", options.submit, "Submit the scripts with sbatch and print the job ids");
  app.add_option("--mem", options.mem, "Memory per task (sbatch --mem, e.g. 4G), array and merge");
  app.add_option("--mem-per-cpu", options.mem_per_cpu, "Memory per CPU (sbatch --mem-per-cpu), array and merge");
  app.add_option("--account", options.account, "Account charged (sbatch --account), array and merge");
  app.add_option("--qos", options.qos, "Quality of service (sbatch --qos), array and merge");
  app.add_option("--gres", options.gres, "Generic resources per task (sbatch --gres, e.g. gpu:1), array only");
  app.add_option("--constraint", options.constraint, "Node features (sbatch --constraint), array only");
  app.add_option("--array-throttle", options.array_throttle, "At most K tasks of the array at once (--array=...%K)");
  app.add_option("--job-timeout", options.job_timeout,
                 "Stop each job after this many seconds (armfarm run --timeout in each task; 0: none)");
  app.add_option("--sbatch-arg", options.sbatch_args,
                 "One more sbatch option for both scripts (repeatable), e.g. --sbatch-arg=--mail-type=END");
  app.add_option("--setup", options.setup,
                 "A file both scripts source before armfarm runs (module load lines, a virtual environment)");
  app.add_flag("--retry-failed", options.retry_failed,
               "Run failed, diverged and timed-out jobs again (by default they are results and stay)");
  app.add_option("--signal-before", options.signal_before,
                 "Seconds before the time limit at which Slurm warns a task (SIGUSR1): it lets the jobs that can "
                 "end in time finish, stops the others and saves (0: chosen from the job-cost model)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  app.add_flag("--requeue,!--no-requeue", options.requeue,
               "A task stopped by the warning (time limit, preemption) requeues itself and resumes its shard")
      ->capture_default_str();
  app.add_option("--max-requeues", options.max_requeues,
                 "A warned task requeues itself only while it has restarted fewer times than this (SLURM_RESTART_COUNT)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  app.add_flag("--dry-run", options.dry_run, "Print the scripts and the submit commands; write and submit nothing");
  app.add_flag("--missing", options.missing,
               "Name the jobs not finished in DB and their shards (the merge job runs it), exit 1 if any; write and submit nothing");
}

/// The options' own checks, before the spec is read; throws std::invalid_argument.
void check_slurm_options(const SlurmOptions& options) {
  if (options.tasks < 1) throw std::invalid_argument("--tasks " + std::to_string(options.tasks) + ": needs at least 1");
  if (options.cpus_per_task < 1) {
    throw std::invalid_argument("--cpus-per-task " + std::to_string(options.cpus_per_task) + ": needs at least 1");
  }
  if (!options.time_limit.empty()) check_slurm_time_limit(options.time_limit);
  if (!options.partition.empty()) check_slurm_partition(options.partition);
  if (!options.mem.empty()) check_slurm_memory("--mem", options.mem);
  if (!options.mem_per_cpu.empty()) check_slurm_memory("--mem-per-cpu", options.mem_per_cpu);
  if (!options.mem.empty() && !options.mem_per_cpu.empty()) {
    throw std::invalid_argument("--mem " + options.mem + ": sbatch takes --mem or --mem-per-cpu, not both");
  }
  const std::pair<const char*, const std::string*> quoted[] = {
      {"--account", &options.account}, {"--qos", &options.qos}, {"--gres", &options.gres},
      {"--constraint", &options.constraint}};
  for (const auto& [option, value] : quoted) make_sbatch_quoted(option, *value);
  if (options.array_throttle < 0) {
    throw std::invalid_argument("--array-throttle " + std::to_string(options.array_throttle) + ": needs at least 1");
  }
  if (!(options.job_timeout >= 0.0 && options.job_timeout < 1e9)) {
    throw std::invalid_argument("--job-timeout: seconds, 0 (none) or more");
  }
  for (const std::string& arg : options.sbatch_args) check_sbatch_arg(arg);
  if (!options.setup.empty()) {
    std::ifstream setup(options.setup);
    if (!setup || fs::is_directory(options.setup)) {
      throw std::invalid_argument("--setup " + options.setup + ": cannot read that file");
    }
  }
}

/// The sweep of --spec, with at least --tasks jobs; throws SpecError or std::invalid_argument.
ExpandedSweep load_slurm_sweep(const SlurmOptions& options) {
  const JobKind kind = make_job_kind_from_environment();
  ExpandedSweep sweep = expand_sweep(load_sweep_spec(options.spec, kind.schema), kind.schema);
  if (options.tasks > static_cast<int>(sweep.jobs.size())) {
    throw std::invalid_argument("--tasks " + std::to_string(options.tasks) + ": more tasks than the " +
                                std::to_string(sweep.jobs.size()) + " jobs of " + options.spec);
  }
  return sweep;
}

/// --db made absolute, checked to be a database file path in an existing folder.
std::string make_slurm_db_path(const std::string& db) {
  std::string path = fs::absolute(db).lexically_normal().string();
  check_slurm_db_path(path);
  if (fs::is_directory(path)) throw std::invalid_argument(db + ": is a directory, not a database file");
  if (!fs::is_directory(fs::path(path).parent_path())) {
    throw std::invalid_argument(db + ": its folder does not exist");
  }
  return path;
}

/// Everything the scripts are made from but the shards to submit and the warning time.
void fill_slurm_plan(const SlurmOptions& options, const ExpandedSweep& sweep, SlurmPlan& plan) {
  plan.armfarm = fs::read_symlink("/proc/self/exe").string();
  plan.spec = fs::absolute(options.spec).lexically_normal().string();
  plan.work_dir = fs::current_path().string();
  plan.sweep = sweep.spec.name;
  plan.jobs = static_cast<int>(sweep.jobs.size());
  plan.tasks = options.tasks;
  plan.time_limit = options.time_limit;
  plan.partition = options.partition;
  plan.cpus_per_task = options.cpus_per_task;
  plan.mem = options.mem;
  plan.mem_per_cpu = options.mem_per_cpu;
  plan.account = options.account;
  plan.qos = options.qos;
  plan.gres = options.gres;
  plan.constraint = options.constraint;
  plan.array_throttle = options.array_throttle;
  plan.job_timeout = options.job_timeout;
  plan.sbatch_args = options.sbatch_args;
  plan.retry_failed = options.retry_failed;
  if (!options.setup.empty()) plan.setup = fs::absolute(options.setup).lexically_normal().string();
  plan.requeue = options.requeue;
  plan.max_requeues = options.max_requeues;
}

/// What is done already: in DB (a finished earlier submission) and in the shard files.
struct FinishedJobs {
  int in_db = 0;
  std::set<std::string> in_db_keys, in_shards_keys;
};

FinishedJobs find_finished_jobs(const ExpandedSweep& sweep, const SlurmPlan& plan) {
  std::vector<std::string> keys;
  for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
  FinishedJobs finished;
  finished.in_db = count_done_jobs(plan.db, keys, plan.retry_failed, finished.in_db_keys);
  for (int shard = 1; shard <= plan.tasks; ++shard) {
    count_done_jobs(make_shard_db_path(plan.db, shard), keys, plan.retry_failed, finished.in_shards_keys);
  }
  std::cout << "sweep " << plan.sweep << ": " << plan.jobs << " jobs, " << finished.in_db << " finished in " << plan.db
            << ", " << finished.in_shards_keys.size() << " finished in its " << plan.tasks << " shard files" << std::endl;
  return finished;
}

/// Only the shards with something left to do are submitted again (all when none looks complete).
void choose_resubmitted_shards(SlurmPlan& plan) {
  for (int shard = 1; shard <= plan.tasks; ++shard) {
    if (!is_shard_complete(plan.db, shard, plan.sweep, plan.retry_failed)) plan.shards.push_back(shard);
  }
  if (static_cast<int>(plan.shards.size()) == plan.tasks) plan.shards.clear();
  if (!plan.shards.empty()) {
    std::cout << "resubmitting " << plan.shards.size() << " of " << plan.tasks << " shards (the others are complete):";
    for (const int shard : plan.shards) std::cout << " " << shard;
    std::cout << "\n";
  }
}

/// The warning time from the expected wall times, calibrated by the jobs DB finished before.
void choose_warning_time(const SlurmOptions& options, const ExpandedSweep& sweep, SlurmPlan& plan) {
  std::optional<ResultsStore> reference;
  if (fs::exists(plan.db)) reference = ResultsStore::open(plan.db, ResultsStore::Mode::read_only);
  const JobKind kind = make_job_kind_from_environment();
  const std::vector<double> seconds = calc_job_seconds(sweep, kind.estimate_cost, reference ? &*reference : nullptr);
  const double longest = seconds.empty() ? 0.0 : *std::max_element(seconds.begin(), seconds.end());
  plan.signal_before = options.signal_before > 0 ? options.signal_before : choose_signal_before(seconds, plan.time_limit);
  std::cout << "warning signal " << plan.signal_before << " s before a task's time limit ("
            << (options.signal_before > 0 ? "--signal-before" : "from the job-cost model") << "; the longest job is expected to take "
            << make_duration_text(longest) << (reference ? " as measured in " + plan.db : "") << "): running jobs expected to end within "
            << calc_stop_grace(plan.signal_before) << " s finish, the others stop and stay pending\n";
  const std::optional<long> limit = plan.time_limit.empty() ? std::nullopt : calc_slurm_time_seconds(plan.time_limit);
  if (limit && longest > static_cast<double>(*limit - plan.signal_before)) {
    std::cout << "armfarm slurm: warning: the longest job is expected to take " << make_duration_text(longest)
              << ", more than a task's --time " << plan.time_limit << " less the warning (" << *limit - plan.signal_before
              << " s): it may never finish and its task be requeued again and again\n";
  }
}

/// The submit commands: the array and the merge after it, or the merge alone.
std::vector<std::string> make_commands(const SlurmPlan& plan, bool array_needed) {
  return array_needed ? make_submit_commands(plan)
                      : std::vector<std::string>{"sbatch --parsable " + make_shell_quoted(make_merge_script_path(plan.db))};
}

/// --dry-run: the scripts and the commands, nothing written.
void print_dry_run(const SlurmPlan& plan, bool array_needed) {
  const std::string array_script = make_array_script_path(plan.db);
  const std::string merge_script = make_merge_script_path(plan.db);
  if (array_needed) std::cout << "--- " << array_script << "\n" << make_array_script(plan);
  std::cout << "--- " << merge_script << "\n" << make_merge_script(plan) << "--- submit with (dry run: nothing written)\n";
  for (const std::string& command : make_commands(plan, array_needed)) std::cout << "  " << command << "\n";
}

/// Writes the scripts (the array's only when needed; without it the shards are marked saved).
void write_scripts(const SlurmPlan& plan, bool array_needed) {
  const std::string array_script = make_array_script_path(plan.db);
  const std::string merge_script = make_merge_script_path(plan.db);
  if (array_needed) write_script(array_script, make_array_script(plan));
  write_script(merge_script, make_merge_script(plan));
  if (array_needed) {
    std::cout << "wrote " << array_script << " (array of " << plan.tasks << " tasks, " << plan.cpus_per_task
              << " CPU" << (plan.cpus_per_task == 1 ? "" : "s") << " each) and " << merge_script << "\n";
  } else {
    // Every job is done in the shard files, read just now: each shard's results are saved.
    for (int shard = 1; shard <= plan.tasks; ++shard) std::ofstream(make_shard_saved_path(plan.db, shard));
    std::cout << "every job is finished in the shard files: only the merge is needed\nwrote " << merge_script << "\n";
  }
}

/// Submits the written scripts: the array, then the merge after it (or the merge alone).
void submit_scripts(const SlurmPlan& plan, bool array_needed) {
  const std::string array_script = make_array_script_path(plan.db);
  const std::string merge_script = make_merge_script_path(plan.db);
  if (!array_needed) {
    const std::string merge_id = run_sbatch(make_commands(plan, false)[0], "merge job");
    std::cout << "submitted merge job " << merge_id << "\n";
    return;
  }
  const std::string array_id = run_sbatch("sbatch --parsable " + make_shell_quoted(array_script), "job array");
  std::cout << "submitted array job " << array_id << " (" << plan.tasks << " tasks)" << std::endl;
  std::string merge_id;
  try {
    merge_id = run_sbatch("sbatch --parsable --dependency=afterany:" + array_id + " " + make_shell_quoted(merge_script),
                          "merge job");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + "; the array job " + array_id + " is queued: submit the merge by hand: sbatch --dependency=afterany:" + array_id + " " + make_shell_quoted(merge_script));
  }
  std::cout << "submitted merge job " << merge_id << " (after array job " << array_id << " ends)\n";
}

}  // namespace

RunFunction setup_slurm(CLI::App& parent) {
  auto options = std::make_shared<SlurmOptions>();
  CLI::App* app = parent.add_subcommand(
      "slurm", "Write (and with --submit submit) sbatch scripts running a sweep as a Slurm job array of shards plus a merge");
  add_slurm_options(*app, *options);

  return [options] {
    SlurmPlan plan;
    ExpandedSweep sweep;
    try {
      check_slurm_options(*options);
      sweep = load_slurm_sweep(*options);
      plan.db = make_slurm_db_path(options->db);
    } catch (const SpecError& e) {
      for (const std::string& line : e.lines()) std::cerr << "armfarm: " << line << "\n";
      return 2;
    } catch (const std::invalid_argument& e) {
      std::cerr << "armfarm: " << e.what() << "\n";
      return 2;
    }
    fill_slurm_plan(*options, sweep, plan);
    const FinishedJobs finished = find_finished_jobs(sweep, plan);
    if (options->missing) {
      print_missing_jobs(sweep, plan, finished.in_db_keys);
      return finished.in_db == plan.jobs ? 0 : 1;
    }
    if (finished.in_db == plan.jobs) {
      std::cout << "nothing to submit: every job is finished in " << plan.db << "\n";
      return 0;
    }
    const bool array_needed = static_cast<int>(finished.in_shards_keys.size()) < plan.jobs;
    if (array_needed) choose_resubmitted_shards(plan);
    choose_warning_time(*options, sweep, plan);
    if (options->dry_run) {
      print_dry_run(plan, array_needed);
      return 0;
    }
    write_scripts(plan, array_needed);
    if (!options->submit) {
      std::cout << "submit with:\n";
      for (const std::string& command : make_commands(plan, array_needed)) std::cout << "  " << command << "\n";
      return 0;
    }
    submit_scripts(plan, array_needed);
    return 0;
  };
}

}  // namespace armfarm::cli
