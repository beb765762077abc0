#pragma once
// Which job `armfarm run`/`expand`/`status`/`slurm` run. The runner library knows the job only as a
// JobKind (its configuration schema, executor and cost estimate); the executable chooses which, by
// linking one definition of make_job_kind:
//   - armfarm, the product: the experiment job (runner/cli/experiment_job_kind.cpp);
//   - armfarm_fakejobs, a test-only binary: the cheap deterministic fake job of the runner's own
//     tests (tests/support/fake_job_kind.cpp, tests/support/fake_job.hpp).
// So the product contains no test double and no switch to one (tests/runner/product_binary).
#include "runner/execution/job_cost.hpp"
#include "runner/execution/job_executor.hpp"

#include <string>

namespace armfarm {

struct JobKind {
  std::string name;  ///< "experiment" (the fake job of the test binary: "fake")
  JobConfigSchema schema;
  JobExecutor executor;
  JobCostFunction estimate_cost;  ///< for --shard (job_cost.hpp)
};

/// The experiment job. `db_path`: the results database whose stored learned models the
/// experiment's jobs may start from (learning.initial_model); "" for none.
JobKind make_experiment_job_kind(const std::string& db_path = "");

/// The job kind of this executable (see above); `db_path` as for make_experiment_job_kind.
/// Defined by the executable, not by the runner library.
JobKind make_job_kind(const std::string& db_path = "");

}  // namespace armfarm
