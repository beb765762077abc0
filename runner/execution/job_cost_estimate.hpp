#pragma once
// A job's relative cost, from its JSON configuration alone (no model is loaded): the control
// ticks it will simulate over all its passes, the figure the runner's ETA weighs finished jobs'
// wall times by. Only ratios between jobs of one sweep matter; the unit is "ticks".
#include <nlohmann/json.hpp>

namespace armfarm {

/// Experiment job: ticks of one pass (sine: duration/dt; figure-eight: points × loops;
/// reaching: points × reaches; recorded: loops × 1000, its length being unknown here) times the
/// passes (batch: collect_repeats + 1), doubled when a held-out evaluation runs. Fake job
/// (runner/execution/fake_job.hpp): its sleep in ms plus its work loop / 1e4. Anything else, or
/// a configuration missing these keys: 1. Always > 0.
double estimate_job_cost(const nlohmann::json& config);

}  // namespace armfarm
