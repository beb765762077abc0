#pragma once
// Which job `armfarm run`/`expand` runs: the experiment job, or — when the environment
// variable ARMFARM_FAKE_JOBS=1 is set, a testing aid for the runner's own tests and
// benchmarks — the cheap deterministic fake job (runner/execution/fake_job.hpp).
#include "runner/execution/job_cost.hpp"
#include "runner/execution/job_executor.hpp"

#include <string>

namespace armfarm {

struct JobKind {
  std::string name;  ///< "experiment" or "fake"
  JobConfigSchema schema;
  JobExecutor executor;
  JobCostFunction estimate_cost;  ///< for --shard (job_cost.hpp)
};

JobKind make_job_kind_from_environment();

}  // namespace armfarm
