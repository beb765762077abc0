#pragma once
// A job's workload, the engine's half of the cost model: what a job will cost in work, from its
// configuration alone (control ticks per pass and over all its passes, learner updates, SSGPR
// work), and the bounds that its one validation holds it to (job_config_validation.hpp), so that
// a typo cannot occupy a core for days. The runner's job-cost model (its estimate in
// joint-seconds for shards, stop graces and Slurm, runner/execution/job_cost.hpp) starts from the
// same control ticks.
#include "engine/experiment/config_problem.hpp"
#include "engine/experiment/job_config.hpp"

#include <vector>

namespace armfarm {

/// Bounds on a job's cost, so that a typo cannot occupy a core for days. At the measured
/// 45 simulated seconds per wall second of the default job (dt = 0.01 s, 7 joints, online LWPR;
/// sweeps/README.md), 5e6 control ticks take about 20 minutes of wall time.
struct JobCostLimits {
  double max_control_ticks = 5e6;    ///< over all passes (batch: collect_repeats + 1; held-out: 1 + one per checkpoint)
  double max_learner_updates = 2e7;  ///< online ticks, or epochs × training samples (+ evaluation updates)
  /// SSGPR: updates × (2·features)² + fit_samples³ × fit_iterations. At the measured ~0.5 µs per
  /// (2D)²/1000 of an update (engine/ssgpr/README.md: 478 µs at D = 500) and ~2.5e9 fit units
  /// per second, 4e12 is about half an hour of wall time.
  double max_ssgpr_work = 4e12;
};

/// Control ticks of one pass over the configured trajectory at `config.simulation.dt`
/// (sine: duration/dt; figure-eight: points × loops; reaching: points × reaches; recorded:
/// length/dt × loops, 0 when no samples are loaded). Real-valued so that nothing overflows.
double calc_ticks_per_pass(const JobConfig& config);

/// Control ticks of one held-out pass over the held-out trajectory of a job with `n` active
/// joints (engine/experiment/heldout_evaluation.hpp; the job makes one collection pass and one
/// control pass per checkpoint over it); 0 when the job has no held-out evaluation.
double calc_heldout_ticks_per_pass(const JobConfig& config, int n);

/// A job's work as the cost bound counts it.
struct JobWorkload {
  double ticks_per_pass = 0.0;          ///< calc_ticks_per_pass
  double passes = 1.0;                  ///< training and control passes: 1, batch: collect_repeats + 1
  double heldout_ticks_per_pass = 0.0;  ///< calc_heldout_ticks_per_pass
  double heldout_passes = 0.0;          ///< 1 collection + 1 per checkpoint (at least 1); 0 without held-out evaluation
  double training_ticks = 0.0;          ///< passes × ticks_per_pass
  double control_ticks = 0.0;           ///< training_ticks + heldout_passes × heldout_ticks_per_pass
  /// Online: one per tick of a pass; batch: epochs × the training samples (rounded
  /// train_fraction × collect_repeats × ticks_per_pass), plus a pass when it learns during
  /// evaluation; 0 otherwise.
  double learner_updates = 0.0;
};

/// The workload of `config` with `n` active joints.
JobWorkload calc_job_workload(const JobConfig& config, int n);

/// The problems of a job over `limits` (empty: within them): too many control ticks (blamed on
/// the trajectory's length key, or on learning.heldout_checkpoints when the held-out passes tip
/// it over), too many learner updates (learning.epochs in batch), too much SSGPR work
/// (learning.ssgpr.features). Judged only on sane counts: validate() calls it when dt, the
/// trajectory and the learning keys have no problem.
std::vector<ConfigProblem> find_cost_problems(const JobConfig& config, int n, const JobCostLimits& limits = {});

}  // namespace armfarm
