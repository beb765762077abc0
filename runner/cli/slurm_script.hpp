#pragma once
// The text of what `armfarm slurm` submits: an sbatch script for a job array whose task I
// (1-based: SLURM_ARRAY_TASK_ID + 1) runs shard I/N of a sweep into its own database file
// `<DB>.shard-I.db`, and an sbatch script for the job that merges the N shard files into DB
// once the array has ended, however its tasks did (`--dependency=afterany`). Pure functions of
// the plan: no I/O.
#include <optional>
#include <string>
#include <vector>

namespace armfarm::cli {

/// One sweep on Slurm. Paths are absolute (the tasks run wherever Slurm puts them).
struct SlurmPlan {
  std::string armfarm;    ///< the armfarm binary the tasks run (on a filesystem every node sees)
  std::string spec;       ///< the sweep spec
  std::string db;         ///< the merged database; its shards and the scripts and logs sit beside it
  std::string work_dir;   ///< the tasks' working directory
  std::string sweep;      ///< the sweep's name (names the Slurm jobs)
  int jobs = 0;           ///< jobs in the sweep (stated in the scripts' comments)
  int tasks = 1;          ///< array tasks = shards, 1..jobs
  std::string time_limit; ///< sbatch --time text per task and for the merge; empty: the partition's default
  std::string partition;  ///< sbatch --partition; empty: the cluster's default
  int cpus_per_task = 1;  ///< sbatch --cpus-per-task; each task runs that many jobs at once (-j)
  // What a site's policy asks for. Empty (0): not stated, the cluster's default. Each reaches
  // its #SBATCH line quoted (make_sbatch_quoted), the array tasks only unless said otherwise.
  std::string mem;            ///< sbatch --mem per task (array and merge), e.g. 4G
  std::string mem_per_cpu;    ///< sbatch --mem-per-cpu (array and merge)
  std::string account;        ///< sbatch --account (array and merge)
  std::string qos;            ///< sbatch --qos (array and merge)
  std::string gres;           ///< sbatch --gres (array only: the merge needs no GPU)
  std::string constraint;     ///< sbatch --constraint (array only)
  int array_throttle = 0;     ///< at most this many tasks at once (--array=0-N%K); 0: no limit
  double job_timeout = 0.0;   ///< `armfarm run --timeout` in each task, seconds; 0: none
  std::vector<std::string> sbatch_args;  ///< more sbatch options, one #SBATCH line each (both scripts)
  std::string setup;          ///< a file both scripts source before armfarm runs (module load, ...); empty: none
  std::vector<int> shards;    ///< the shards (1-based) the array runs; empty: all 1..tasks
  bool retry_failed = false;  ///< run failed, diverged and timed-out jobs again (else they are results: `run --keep-failed`)
  /// Seconds before the time limit at which Slurm warns the task (SIGUSR1); `armfarm slurm`
  /// chooses it from the job-cost model (choose_signal_before) unless --signal-before is given.
  int signal_before = 300;
  bool requeue = true;        ///< a warned task that stopped early requeues itself (scontrol requeue)
  /// A task requeues itself only while it has restarted fewer times than this (SLURM_RESTART_COUNT),
  /// so that a job that never fits in --time less the warning does not requeue it forever.
  int max_requeues = 20;
};

/// "<db>.shard-<shard>.db", shard 1-based.
std::string make_shard_db_path(const std::string& db, int shard);
/// "<db>.array.sbatch" and "<db>.merge.sbatch": where `armfarm slurm` writes the two scripts.
std::string make_array_script_path(const std::string& db);
std::string make_merge_script_path(const std::string& db);

/// "<db>.shard-<shard>.saved": written by shard <shard>'s task once its `armfarm run` has saved
/// every outcome (exit 0 or 1), removed when the task starts. The merge requires all of them.
std::string make_shard_saved_path(const std::string& db, int shard);

/// The job array's sbatch script. A task's `armfarm run` exit status 1 (jobs ran and some
/// failed, diverged or timed out, all recorded) counts as success so that the merge still
/// brings those results in, and marks the shard saved; those jobs are not run again by a
/// resubmission unless plan.retry_failed; any other status (bad input, results not
/// saved on a full disk, the task killed) fails the task and leaves the shard unmarked.
/// No user string (sweep name, paths) reaches the script but single-quoted, or in a comment with
/// control characters replaced.
std::string make_array_script(const SlurmPlan& plan);
/// The merge job's sbatch script: `armfarm merge DB <the shard files marked saved>`, then
/// `armfarm status DB`; when shards are missing it names them ("… and N more") and exits 1.
std::string make_merge_script(const SlurmPlan& plan);

/// The shell commands that submit the two scripts (the merge after the array), as printed.
std::vector<std::string> make_submit_commands(const SlurmPlan& plan);

/// Throws std::invalid_argument ("--time 1:2:3:4: ...") unless `text` is one of sbatch's time
/// forms: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S (S, and M after an hour, below 60; H after a day
/// below 24) or "infinite"/"unlimited".
void check_slurm_time_limit(const std::string& text);
/// The seconds of a time limit in one of the forms check_slurm_time_limit takes; nullopt for
/// "infinite"/"unlimited". Precondition: check_slurm_time_limit(text) passed.
std::optional<long> calc_slurm_time_seconds(const std::string& text);

/// The warning time T (seconds before a task's time limit, sbatch --signal=B:USR1@T) from the
/// jobs' expected wall times (calc_job_seconds): room for the longest job to finish once more,
/// 1.5 × its time plus the reserve of calc_stop_grace, at least 60 s (Slurm checks time limits
/// about once a minute, so the warning may come up to that much early), at most 65535, and at
/// most half of `time_limit` when one is set (else a task would be warned as it starts).
int choose_signal_before(const std::vector<double>& job_seconds, const std::string& time_limit);

/// `armfarm run --stop-grace` for a warning `signal_before` seconds ahead: that less a reserve
/// for committing, exiting and `scontrol requeue` (a tenth of it, at least 5 s; 0 at the least).
int calc_stop_grace(int signal_before);

/// Throws std::invalid_argument unless `text` is a comma-separated list of partition names
/// (letters, digits, '_', '-', '.').
void check_slurm_partition(const std::string& text);
/// Throws std::invalid_argument when `path` (the database) holds a character that sbatch
/// directives or its output-file patterns cannot carry: white space, quotes, '\\', '%', control
/// characters.
void check_slurm_db_path(const std::string& path);

/// `text` quoted for a POSIX shell ('...' with embedded ' as '\'').
std::string make_shell_quoted(const std::string& text);
/// `text` quoted for an #SBATCH line, which sbatch splits itself: '...' with ' and \\ escaped
/// by a backslash (inside quotes sbatch takes a backslash as escaping the next character).
/// Throws std::invalid_argument for control characters (a newline would end the directive and
/// start a shell line).
std::string make_sbatch_quoted(const std::string& option, const std::string& text);

/// Throws std::invalid_argument unless `text` is a memory size as sbatch takes it: digits with
/// an optional unit K, M, G or T (either case).
void check_slurm_memory(const std::string& option, const std::string& text);
/// Throws std::invalid_argument unless `text` is one sbatch option ("--name[=value]" or "-x"),
/// not one `armfarm slurm` writes itself (--array, --dependency, --output, --job-name).
void check_sbatch_arg(const std::string& text);

}  // namespace armfarm::cli
