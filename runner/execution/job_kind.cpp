#include "runner/execution/job_kind.hpp"

#include "runner/execution/stored_models.hpp"

namespace armfarm {

JobKind make_experiment_job_kind(const std::string& db_path) {
  auto stored = std::make_shared<StoredModels>(db_path);
  return {"experiment", make_experiment_config_schema(stored), make_experiment_executor(stored), make_experiment_cost_function()};
}

}  // namespace armfarm
