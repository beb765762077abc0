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
  Shard shard;
  std::vector<double> job_costs;           ///< per job of the sweep, to deal shards (job_cost.hpp); empty: 1 each
  ClaimConfig claims;                      ///< runners sharing the database (claim_keeper.hpp)
  ProgressStyle progress = ProgressStyle::quiet;
  std::ostream* progress_out = nullptr;    ///< required unless quiet
  Provenance provenance;
};

struct RunSummary {
  int jobs_in_sweep = 0;
  int jobs_in_shard = 0;
  int skipped = 0;  ///< already done
  int run = 0;      ///< attempted and recorded
  int done = 0, failed = 0, diverged = 0, timeout = 0;
  int abandoned = 0;  ///< not started or interrupted because of a stop request
  int done_elsewhere = 0;  ///< done by another runner on the same database while this one ran
  int taken_over = 0;      ///< stale claims of other runners this run took over (or found at its start)
  bool interrupted = false;
  double elapsed_seconds = 0.0;
  std::vector<std::string> failures;  ///< "key  params: status: message"
  /// True when every job of the shard is done.
  bool all_done() const { return failed + diverged + timeout + abandoned == 0 && !interrupted; }
};

/// Runs `sweep`'s jobs of `options.shard`. `stop_requested` (e.g. from StopSignalScope) stops
/// taking jobs and asks running ones to stop; what finished stays recorded, interrupted jobs go
/// back to pending. Throws StoreError when the database cannot be written.
RunSummary run_sweep(const ExpandedSweep& sweep, const JobExecutor& executor, const RunOptions& options,
                     const std::atomic<bool>& stop_requested);

/// "3f2a1b7c init_D=25 gain_scale=2": the first 8 digits of the key and the varying parameters.
std::string make_job_label(const ExpandedJob& job);

}  // namespace armfarm
