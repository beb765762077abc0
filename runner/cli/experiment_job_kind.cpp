// The armfarm executable runs the experiment job (runner/execution/job_kind.hpp).
#include "runner/execution/job_kind.hpp"

namespace armfarm {

JobKind make_job_kind(const std::string& db_path) { return make_experiment_job_kind(db_path); }

}  // namespace armfarm
