#pragma once
// What a job costs, for dealing a sweep's jobs to shards (shard.hpp) so that shards finish
// together. An estimate from the configuration alone: simulated seconds over all passes (the
// job-cost model's control ticks, engine/experiment/job_workload.hpp) × active joints × a
// learning-mode factor (the experiment job; the fake job has its own), in "joint-seconds". Calibrated when a reference database of finished jobs is given: a job done
// there costs its measured wall time; another job costs its estimate times the measured wall
// seconds per estimated unit of the finished jobs of its kind (learning mode, trajectory kind,
// active joints), or of all finished jobs when none is of its kind.
#include "results/results_store.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace armfarm {

struct JobCostEstimate {
  double cost = 1.0;     ///< estimated units (> 0)
  std::string kind;      ///< jobs of one kind share a measured rate: "batch sine 7 joints"
  double seconds = 1.0;  ///< estimated wall time on one core, s (> 0): what the stop grace and Slurm's warning time go by
};

/// Estimates one resolved job configuration; `checked` as for JobExecutor (null: the estimate
/// reads `config` itself, e.g. a finished job of a reference database). Throws std::exception
/// when it cannot.
using JobCostFunction = std::function<JobCostEstimate(const nlohmann::json& config, const CheckedConfig* checked)>;

/// Learning-mode factors of the experiment job's estimate: wall time per simulated second and
/// active joint relative to a job without learner. Measured with `armfarm job` on the default
/// sine, 7 joints, no held-out pass (2-core machine shared with other builds, load ≈ 19; times
/// of one run each, alternated): 40 s online 9.87/10.03 s against none 8.73/8.88 s (1.13); batch
/// per pass (3 passes of 12 s: 9.82/8.68 s) as none (3.16/3.01 s per 12 s pass). The physics
/// dominates; LWPR adds about 15 % online.
struct JobCostModel {
  double none_factor = 1.0;
  double online_factor = 1.15;  ///< LWPR update + prediction every tick
  double batch_factor = 1.0;    ///< per pass: collection passes and the control pass (training not counted)
  /// Wall seconds per unit on one core, for JobCostEstimate::seconds: the runs above give
  /// 9.87 s / (40 s × 7 × 1.15) = 0.031 online and 3.16 s / (12 s × 7) = 0.038 without learner;
  /// rounded up, so that a job is rather expected to take longer than it does.
  double seconds_per_unit = 0.04;
};

/// The experiment job's estimate (loads each model file once, and makes the job's arm with
/// make_job_model as the executor does: job_models.hpp).
JobCostFunction make_experiment_cost_function(const JobCostModel& model = {});

/// The cost of every job of `sweep` (in expansion order): the estimates, calibrated by the done
/// jobs of `reference` when given (see above). Deterministic: depends only on the jobs and the
/// reference file's contents.
std::vector<double> calc_job_costs(const ExpandedSweep& sweep, const JobCostFunction& estimate,
                                   const ResultsStore* reference = nullptr);

/// The expected wall time of every job of `sweep` on one core, s (in expansion order): each
/// estimate's `seconds`, or, when `reference` has done jobs, calibrated by them as the costs are
/// (a job done there: its measured wall time). Deterministic like calc_job_costs.
std::vector<double> calc_job_seconds(const ExpandedSweep& sweep, const JobCostFunction& estimate,
                                     const ResultsStore* reference = nullptr);

}  // namespace armfarm
