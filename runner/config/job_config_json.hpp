#pragma once
// The experiment job's configuration as JSON: the default tree (every key, its default and
// so its type; sweeps/README.md documents each) and the parser from a fully resolved
// configuration (defaults merged) to the engine's JobConfig.
#include "engine/experiment/job_config.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// Every key of a job configuration with its default. `null` marks keys whose default is the
/// engine's rule (e.g. learning.lwpr.init_D, norm_in) and that accept a number or a list.
nlohmann::json make_job_config_defaults();

/// Parses a resolved configuration for an arm with `movable_joints` movable joints. Throws
/// ConfigError (runner/execution/job_executor.hpp) with the JSON path of the offending value.
JobConfig parse_job_config(const nlohmann::json& config, int movable_joints);

}  // namespace armfarm
