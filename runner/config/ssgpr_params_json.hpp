#pragma once
// SSGPR parameters from JSON (`armfarm fit --learner ssgpr --params`), read through the key
// table of a job's learning.ssgpr block (ssgpr_learning_config_keys() in
// engine/learning/ssgpr_learning_config.hpp), so a params file and a spec's block use the same
// names, ranges and defaults. Lengthscales are in units of each input column's standard
// deviation, as in a job with learning.normalize_inputs.
#include "engine/learning/ssgpr_learning_config.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// Parses `json` (an object of learning.ssgpr keys) over the job defaults. Throws
/// std::runtime_error "source: key: what" for an unknown key, a wrong type or a value out of
/// the key's range; list sizes are checked when the learner is built.
SsgprLearningConfig parse_ssgpr_params(const nlohmann::json& json, const std::string& source);

/// Reads and parses a params file (see parse_ssgpr_params).
SsgprLearningConfig load_ssgpr_params(const std::string& path);

}  // namespace armfarm
