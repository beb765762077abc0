// The test binary armfarm_fakejobs runs the fake job (runner/execution/job_kind.hpp): the runner's
// process tests (runs killed, paused, resumed, merged, sharded, submitted to Slurm) drive it
// through the real command line at almost no CPU. Never linked into the product armfarm.
#include "support/fake_job.hpp"
#include "runner/execution/job_kind.hpp"

namespace armfarm {

JobKind make_job_kind(const std::string&) {
  return {"fake", make_fake_job_config_schema(), make_fake_job_executor(), make_fake_job_cost_function()};
}

}  // namespace armfarm
