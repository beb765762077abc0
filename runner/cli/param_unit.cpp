#include "runner/cli/param_unit.hpp"

#include "engine/experiment/job_config.hpp"

namespace armfarm::cli {

std::string find_param_unit(const std::string& path) {
  const std::string key = path.substr(0, path.find('['));
  for (const JobConfigKey& entry : job_config_keys()) {
    if (entry.path == key) return entry.unit;
  }
  return "";
}

}  // namespace armfarm::cli
