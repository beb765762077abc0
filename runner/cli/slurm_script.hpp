#pragma once
// The text of what `armfarm slurm` submits: an sbatch script for a job array whose task I
// (1-based: SLURM_ARRAY_TASK_ID + 1) runs shard I/N of a sweep into its own database file
// `<DB>.shard-I.db`, and an sbatch script for the job that merges the N shard files into DB
// once the array has succeeded (`--dependency=afterok`). Pure functions of the plan: no I/O.
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
/// brings those results in, and marks the shard saved; any other status (bad input, results not
/// saved on a full disk, the task killed) fails the task and leaves the shard unmarked.
/// No user string (sweep name, paths) reaches the script but single-quoted, or in a comment with
/// control characters replaced.
std::string make_array_script(const SlurmPlan& plan);
/// The merge job's sbatch script: refuses (exit 1, naming the shards, "… and N more") unless every
/// shard is marked saved; then `armfarm merge DB <the N shard files>`, then `armfarm status DB`.
std::string make_merge_script(const SlurmPlan& plan);

/// The shell commands that submit the two scripts (the merge after the array), as printed.
std::vector<std::string> make_submit_commands(const SlurmPlan& plan);

/// Throws std::invalid_argument ("--time 1:2:3:4: ...") unless `text` is one of sbatch's time
/// forms: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S (S, and M after an hour, below 60; H after a day
/// below 24) or "infinite"/"unlimited".
void check_slurm_time_limit(const std::string& text);
/// Throws std::invalid_argument unless `text` is a comma-separated list of partition names
/// (letters, digits, '_', '-', '.').
void check_slurm_partition(const std::string& text);
/// Throws std::invalid_argument when `path` (the database) holds a character that sbatch
/// directives or its output-file patterns cannot carry: white space, quotes, '\\', '%', control
/// characters.
void check_slurm_db_path(const std::string& path);

/// `text` quoted for a POSIX shell ('...' with embedded ' as '\'').
std::string make_shell_quoted(const std::string& text);

}  // namespace armfarm::cli
