// `armfarm slurm SPEC --db DB --tasks N`: writes the sbatch scripts that run a sweep on a Slurm
// cluster as a job array of N shards, each into its own database file beside DB (one writer per
// SQLite file, never one file shared over a network filesystem), plus a merge job after the
// array; prints the commands that submit them, or with --submit submits them. Run again after
// a partial failure it submits only what is missing (done shards resume as no-ops).
#include "results/results_store.hpp"
#include "runner/cli/slurm_script.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>

namespace armfarm::cli {

namespace {

namespace fs = std::filesystem;

/// How many of `keys` are done in the database at `path` (0 when there is no such file).
int count_done_jobs(const std::string& path, const std::vector<std::string>& keys, std::set<std::string>& done) {
  if (!fs::exists(path)) return 0;
  const ResultsStore store = ResultsStore::open(path, ResultsStore::Mode::read_only);
  int count = 0;
  for (const std::string& key : keys) {
    const std::optional<JobRecord> job = store.find_job(key);
    if (job && job->status == "done") {
      ++count;
      done.insert(key);
    }
  }
  return count;
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

}  // namespace

RunFunction setup_slurm(CLI::App& parent) {
  struct Options {
    std::string spec;
    std::string db;
    int tasks = 0;
    std::string time_limit;
    std::string partition;
    int cpus_per_task = 1;
    bool submit = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "slurm", "Write (and with --submit submit) sbatch scripts running a sweep as a Slurm job array of shards plus a merge");
  app->add_option("spec", options->spec, "Sweep spec (JSON)")->required();
  app->add_option("--db", options->db, "Merged results database; shard files <DB>.shard-I.db, scripts and logs beside it")
      ->required();
  app->add_option("--tasks", options->tasks, "Array tasks = shards of the sweep (1 to the number of jobs)")->required();
  app->add_option("--time", options->time_limit, "Time limit of each task and of the merge, sbatch's form (e.g. 2:00:00)");
  app->add_option("--partition", options->partition, "Slurm partition (default: the cluster's default)");
  app->add_option("--cpus-per-task", options->cpus_per_task, "CPUs per task; each task runs that many jobs at once")
      ->capture_default_str();
  app->add_flag("--submit", options->submit, "Submit the scripts with sbatch and print the job ids");

  return [options] {
    SlurmPlan plan;
    ExpandedSweep sweep;
    try {
      if (options->tasks < 1) throw std::invalid_argument("--tasks " + std::to_string(options->tasks) + ": needs at least 1");
      if (options->cpus_per_task < 1) {
        throw std::invalid_argument("--cpus-per-task " + std::to_string(options->cpus_per_task) + ": needs at least 1");
      }
      if (!options->time_limit.empty()) check_slurm_time_limit(options->time_limit);
      if (!options->partition.empty()) check_slurm_partition(options->partition);
      const JobKind kind = make_job_kind_from_environment();
      sweep = expand_sweep(load_sweep_spec(options->spec, kind.schema), kind.schema);
      if (options->tasks > static_cast<int>(sweep.jobs.size())) {
        throw std::invalid_argument("--tasks " + std::to_string(options->tasks) + ": more tasks than the " +
                                    std::to_string(sweep.jobs.size()) + " jobs of " + options->spec);
      }
      plan.db = fs::absolute(options->db).lexically_normal().string();
      check_slurm_db_path(plan.db);
      if (fs::is_directory(plan.db)) throw std::invalid_argument(options->db + ": is a directory, not a database file");
      if (!fs::is_directory(fs::path(plan.db).parent_path())) {
        throw std::invalid_argument(options->db + ": its folder does not exist");
      }
    } catch (const SpecError& e) {
      for (const std::string& line : e.lines()) std::cerr << "armfarm: " << line << "\n";
      return 2;
    } catch (const std::invalid_argument& e) {
      std::cerr << "armfarm: " << e.what() << "\n";
      return 2;
    }
    plan.armfarm = fs::read_symlink("/proc/self/exe").string();
    plan.spec = fs::absolute(options->spec).lexically_normal().string();
    plan.work_dir = fs::current_path().string();
    plan.sweep = sweep.spec.name;
    plan.jobs = static_cast<int>(sweep.jobs.size());
    plan.tasks = options->tasks;
    plan.time_limit = options->time_limit;
    plan.partition = options->partition;
    plan.cpus_per_task = options->cpus_per_task;

    // What is done already: in DB (a finished earlier submission) and in the shard files.
    std::vector<std::string> keys;
    for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
    std::set<std::string> done_in_db, done_in_shards;
    const int in_db = count_done_jobs(plan.db, keys, done_in_db);
    for (int shard = 1; shard <= plan.tasks; ++shard) {
      count_done_jobs(make_shard_db_path(plan.db, shard), keys, done_in_shards);
    }
    std::cout << "sweep " << plan.sweep << ": " << plan.jobs << " jobs, " << in_db << " done in " << plan.db << ", "
              << done_in_shards.size() << " done in its " << plan.tasks << " shard files" << std::endl;
    if (in_db == plan.jobs) {
      std::cout << "nothing to submit: every job is done in " << plan.db << "\n";
      return 0;
    }
    const bool array_needed = static_cast<int>(done_in_shards.size()) < plan.jobs;

    const std::string array_script = make_array_script_path(plan.db);
    const std::string merge_script = make_merge_script_path(plan.db);
    if (array_needed) write_script(array_script, make_array_script(plan));
    write_script(merge_script, make_merge_script(plan));
    std::vector<std::string> commands = make_submit_commands(plan);
    if (array_needed) {
      std::cout << "wrote " << array_script << " (array of " << plan.tasks << " tasks, " << plan.cpus_per_task
                << " CPU" << (plan.cpus_per_task == 1 ? "" : "s") << " each) and " << merge_script << "\n";
    } else {
      commands = {"sbatch --parsable " + make_shell_quoted(merge_script)};
      // Every job is done in the shard files, read just now: each shard's results are saved.
      for (int shard = 1; shard <= plan.tasks; ++shard) std::ofstream(make_shard_saved_path(plan.db, shard));
      std::cout << "every job is done in the shard files: only the merge is needed\nwrote " << merge_script << "\n";
    }
    if (!options->submit) {
      std::cout << "submit with:\n";
      for (const std::string& command : commands) std::cout << "  " << command << "\n";
      return 0;
    }
    if (!array_needed) {
      const std::string merge_id = run_sbatch(commands[0], "merge job");
      std::cout << "submitted merge job " << merge_id << "\n";
      return 0;
    }
    const std::string array_id = run_sbatch("sbatch --parsable " + make_shell_quoted(array_script), "job array");
    std::cout << "submitted array job " << array_id << " (" << plan.tasks << " tasks)" << std::endl;
    std::string merge_id;
    try {
      merge_id = run_sbatch("sbatch --parsable --dependency=afterok:" + array_id + " " + make_shell_quoted(merge_script),
                            "merge job");
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string(e.what()) + "; the array job " + array_id + " is queued: submit the merge by hand: sbatch --dependency=afterok:" + array_id + " " + make_shell_quoted(merge_script));
    }
    std::cout << "submitted merge job " << merge_id << " (after array job " << array_id << " succeeds)\n";
    return 0;
  };
}

}  // namespace armfarm::cli
