#pragma once
// Runs a sweep with a `search` block (sweeps/README.md, "Search"): decides steps with the
// samplers of runner/search/, runs them as ordinary jobs with run_sweep, and records the search
// in the store (results/search_store.hpp).
//
// Rounds. Each round first *replays* the search from the database: the decisions are taken again
// from the start (calc_next_step), and whenever one needs the objective of step s the job of
// step s is looked up by its key — done: its objective metric at the step's checkpoint (signed
// into a loss by the catalog's direction; NULL → +∞); failed, diverged or timed out: +∞; not yet
// run: the replay stops there. The steps decided so far whose jobs are not finished are run
// (at most `slots` of them: the visibility rule bounds how far decisions run ahead of results),
// then the next round replays again. So the trial sequence is a function of the spec and the
// committed results only: the same at -j1 and -j8, after kill -9 (the killed round's jobs are
// pending and run again), and with several runners on one file (claims share the jobs).
//
// Settings in the file. The `searches` row holds everything a decision depends on
// (results/search_store.hpp). Before its first round a runner that finds its search in the file
// (a resume, or a second runner that started later) compares what the spec decides (method,
// sampler, seed, η, slots, limits, budget, objective, rungs, space, an explicit tpe_startup or
// tpe_rule) and refuses any difference, one line each, before anything is written (SpecError,
// exit 2); what the build decides (each rung's estimated cost, TPE's start-up by the budget rule,
// TPE's γ, good-group cap and candidates, TPE's rule where the spec gives none) it takes from the row, so runners
// of different builds continue one search alike. A row of schema version 6 lacks the last ones:
// the runner's are written, except TPE's rule, which a row of schema 6 or 7 lacks as NULL and
// which is read as the per-axis rule those builds used (and written so). The joint rule's
// constants (TPE's prior weight, bandwidth fraction and liar bandwidth factor, schema 9) are not
// adopted but compared: a joint search recorded with other constants than this build's is
// refused (one line naming the database and the search, exit 2, nothing written), a NULL (a row
// of schema 8) read as the schema-8 build's constants, which are today's.
//
// Rungs are short jobs; promotions rerun. A step to rung r below the last is a job that learns
// exactly to rung r's checkpoint (SpecSearch::length_path: learning.epochs for batch jobs,
// trajectory.reaching.reaches for online reaching jobs) with learning.heldout_checkpoints cut
// after it; the last rung is the base's job. A promotion reruns its trial from scratch to the
// longer rung, costing the whole rung (SearchSettings::resumable = false), and the budget counts
// it. Why not continue from the stored model: a job's state at a checkpoint is more than its
// learner (the plant's state, the trajectory position, the pass statistics and divergence
// monitor, the batch shuffle stream), and jobs cannot start from such a state. The rerun is
// exact for batch jobs: training draws its shuffles in epoch order, so a job cut after epoch e
// is a prefix of the longer one and scores bit-identically at every checkpoint they share
// (search_runner_test, APromotedTrialScoresAsAStraightRunToTheLongerBudget). An online reaching
// job cut after k reaches is not a prefix bit for bit: its inputs are normalised by the
// statistics of its whole (shorter) trajectory, so its rung is a close, not an identical,
// estimate of the longer job's checkpoint. Online jobs over other trajectories run the whole
// pass at every rung (no key sets their length in checkpoints).
//
// Costs. A budget in jobs counts 1 per step. A budget in cpu_seconds counts each rung's job as
// the job-cost model's estimate (job_cost.hpp, joint-seconds) times a fixed, measured
// CPU-seconds per joint-second (calc_search_cpu_seconds): a constant, not this machine's
// timing, so the decisions stay a function of the spec.
#include "runner/execution/job_kind.hpp"
#include "runner/execution/sweep_runner.hpp"

#include <atomic>
#include <string>

namespace armfarm {

struct SearchRunSummary {
  std::size_t steps = 0;
  std::size_t trials = 0;
  std::size_t rounds = 0;
  double spent = 0.0;          ///< in the budget's unit
  bool finished = false;       ///< the search decided it is over and every step is committed
  RunSummary last;             ///< the last round's run_sweep summary
  std::optional<double> best;  ///< the best objective at the last rung (as the metric, not the loss)
  std::size_t best_trial = 0;
};

/// Why a search is not dealt to shards (`run --shard I/N`, `slurm --tasks N` with N > 1), for
/// the one-line refusal after "SPEC: sweep.search: ". A shard runs in a file of its own, and a
/// step is decided over the committed objectives of the steps before it (search_schedule.hpp):
/// whichever way the steps were dealt, a shard would lack the other shards' objectives, so it
/// could not take the decisions one search takes, and waiting for them is not possible across
/// files. A deterministic search needs every result in one database.
inline constexpr const char* kSearchNotShardedReason =
    "a search is not sharded: each step is decided over the objectives of the steps before it, which other shards' "
    "files would hold, so no shard could take the decisions of the one search; run several runners on one database "
    "(one machine), or on N machines N searches with their own names and seeds, then merge the files";

/// CPU-seconds per joint-second of the experiment job's cost estimate. Measured by
/// BM_SearchCostFactor of tests/bench/bench_search.cpp: each job of a shipped spec (its first
/// seed) run alone at -j1, its process CPU over its estimated joint-seconds (2-core machine).
/// On 2026-12-04 (after the LWPR pass-fusion round; load 0.5-0.7): sweeps/quickstart.json 6.92
/// CPU-s for 4208 joint-s (0.0016), sweeps/thesis/fig6_1_kernel_width.json 23.80 for 10080
/// (0.0024), table6_5_7_heldout_reaching 6.84 for 3574 (0.0019); together 37.56 for 17863,
/// 0.0021 (runner/search/README.md, "The cost factor", has the rerun of 2026-12-04 late). It was
/// 0.0044 (2026-12-03, before that round, load 5-9) and 0.0038 before. Per job it is within a
/// factor of about 2, and the figure-eight tables 6.1-6.3 cost 3-4 times their estimate (the
/// model has no term for batch training). The factor enters no job key or metric: it converts a
/// cpu_seconds budget into joint-seconds. A search records what it decides with it: each rung's
/// cost (search_rungs.cost, estimate × factor) and TPE's start-up; a resumed search and a second
/// runner adopt those, and a merge compares them, so a build with another factor continues a
/// stored search unchanged.
inline constexpr double kSearchCpuSecondsPerJointSecond = 0.0021;

/// The CPU-seconds a cpu_seconds budget counts for one job configuration: the experiment job's
/// estimate times kSearchCpuSecondsPerJointSecond; another job kind's (the fake job) estimate as it is.
double calc_search_cpu_seconds(const JobKind& kind, const nlohmann::json& config);

/// Runs `spec` (which has a search) to its end, or until a round is interrupted or fails to
/// write. Throws SpecError, ConfigError or StoreError as expand_sweep and run_sweep do.
SearchRunSummary run_search(const SweepSpec& spec, const JobKind& kind, const RunOptions& options,
                            const ExpansionLimits& limits, const std::atomic<bool>& stop_requested);

}  // namespace armfarm
