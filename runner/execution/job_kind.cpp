#include "runner/execution/job_kind.hpp"

#include "runner/execution/fake_job.hpp"

#include <cstdlib>
#include <cstring>

namespace armfarm {

JobKind make_job_kind_from_environment() {
  const char* fake = std::getenv("ARMFARM_FAKE_JOBS");
  if (fake != nullptr && std::strcmp(fake, "1") == 0) {
    return {"fake", make_fake_job_config_schema(), make_fake_job_executor(), make_fake_job_cost_function()};
  }
  return {"experiment", make_experiment_config_schema(), make_experiment_executor(), make_experiment_cost_function()};
}

}  // namespace armfarm
