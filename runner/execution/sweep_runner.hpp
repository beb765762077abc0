#pragma once
// Runs the jobs of an expanded sweep in parallel on a tbb::task_arena and records them in a
// results database through one writer thread. Resume is the default: jobs already `done`
// (by this or any sweep) are skipped; failed, diverged, timed-out and unfinished ones run
// again. Each job owns its state, so results never depend on the thread count or the order.
// Every job is claimed in the database before it runs (claim_keeper.hpp), so several runners on
// one file share the work; jobs another live runner holds are waited for, then counted as done
// elsewhere or, when that runner's heartbeat stops, taken over.
#include "results/results_store.hpp"
#include "runner/execution/claim_keeper.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/execution/progress_reporter.hpp"
#include "runner/execution/run_headline.hpp"
#include "runner/execution/shard.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <atomic>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace armfarm {

struct RunOptions {
  std::string db_path = "results.db";
  int threads = 0;                         ///< 0: one per core
  std::optional<double> timeout_seconds;   ///< per job, wall clock, s
  bool force = false;                      ///< run done jobs again
  bool rerun_unsuccessful = true;          ///< run failed, diverged and timed-out jobs again (searches: no, their outcome is the trial's)
  Shard shard;
  std::vector<double> job_costs;           ///< per job of the sweep (job_cost.hpp): deals the shards, weights the ETA; empty: 1 each
  /// After a stop request (a signal; not a failed write), a running job whose expected wall time
  /// (job_seconds) ends within this many seconds of the request runs on, for at most that long;
  /// the others stop at once. Unset: every running job stops at once. Either way a stopped job is
  /// not failed: it goes back to pending.
  std::optional<double> stop_grace_seconds;
  const std::atomic<bool>* stop_at_once = nullptr;  ///< set: the stop request waits for no grace (SIGINT, SIGTERM: StopSignalScope)
  std::vector<double> job_seconds;         ///< per job of the sweep, expected wall s (calc_job_seconds); a job without one is not expected to end
  ClaimConfig claims;                      ///< runners sharing the database (claim_keeper.hpp)
  ProgressConfig progress;                 ///< style quiet by default
  std::ostream* progress_out = nullptr;    ///< required unless quiet
  Provenance provenance;
};

struct RunSummary {
  int jobs_in_sweep = 0;
  int jobs_in_shard = 0;
  int skipped = 0;  ///< already done
  int run = 0;      ///< attempted and recorded
  int done = 0, failed = 0, diverged = 0, timeout = 0;
  int abandoned = 0;  ///< not started or interrupted because of a stop request or a failed write
  int done_elsewhere = 0;  ///< done by another runner on the same database while this one ran
  int taken_over = 0;      ///< stale claims of other runners this run took over (or found at its start)
  int not_saved = 0;  ///< finished, but lost because a commit failed (they run again on resume)
  int finished_in_grace = 0;  ///< running at the stop request, let run on (stop_grace_seconds) and finished
  int discarded = 0;  ///< finished after another runner took the claim over: not written (the fence)
  /// Of the discarded ones: not done in the file when this run ended (the runner that took them
  /// over still holds them, or stopped too): the shard is not all done.
  int discarded_not_done = 0;
  std::string write_error;  ///< the failed commit's error ("" when every write succeeded)
  bool interrupted = false;
  double elapsed_seconds = 0.0;
  std::vector<std::string> failures;  ///< "key  params: status: message"
  std::optional<RunHeadline> headline;  ///< best and worst of this run's done jobs by the main metric
  /// True when every job of the shard is done.
  bool all_done() const {
    return failed + diverged + timeout + abandoned + not_saved + discarded_not_done == 0 && !interrupted &&
           write_error.empty();
  }
};

/// Runs `sweep`'s jobs of `options.shard`. `stop_requested` (e.g. from StopSignalScope) stops
/// taking jobs and asks running ones to stop (those expected to end within
/// options.stop_grace_seconds first run on); what finished stays recorded, interrupted jobs go
/// back to pending. A job counts as run (and is reported) only once its result is committed;
/// when a commit fails the run stops taking jobs and returns with `write_error` and `not_saved`
/// set (the lost jobs are not done in the database, so the next run reruns them). Throws
/// StoreError when the database cannot be opened or the sweep cannot be registered.
RunSummary run_sweep(const ExpandedSweep& sweep, const JobExecutor& executor, const RunOptions& options,
                     const std::atomic<bool>& stop_requested);

/// "3f2a1b7c init_D=25 gain_scale=2": the first 8 digits of the key and the varying parameters.
std::string make_job_label(const ExpandedJob& job);

}  // namespace armfarm
