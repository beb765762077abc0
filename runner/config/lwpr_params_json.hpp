#pragma once
// LWPR parameters from JSON (`armfarm lwpr fit --params`), read through LWPR's key table
// (lwpr_params_keys() in engine/learning/learning_config.hpp, the same table as a job's
// learning.lwpr block): the published library's key names plus ours (max_fields, cutoff,
// trust_n_data). Library conventions are accepted too: flags as 0/1, "Gaussian"/"BiSquare".
// Missing keys keep lwpr::LwprParams{}'s library defaults (init_D 25, for raw data). Unknown
// keys are errors.
#include "engine/lwpr/lwpr_params.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// Per-dimension standard deviations of the training data, used when norm_in / norm_out is "std".
struct LwprDataScales {
  Eigen::VectorXd input_std;
  Eigen::VectorXd output_std;
};

/// Parses `json` (an object) into LwprParams for n_in inputs. init_D: number, list (diagonal) or
/// list of lists (full). norm_in/norm_out: number, list, or "std" (taken from `scales`). Throws
/// std::runtime_error "source: key: what" for unknown keys (with a suggestion) and bad values.
lwpr::LwprParams parse_lwpr_params(const nlohmann::json& json, const std::string& source, int n_in,
                                   const LwprDataScales& scales);

/// Reads and parses a params file (see parse_lwpr_params).
lwpr::LwprParams load_lwpr_params(const std::string& path, int n_in, const LwprDataScales& scales);

}  // namespace armfarm
