#pragma once
// LWPR parameters from JSON, with the published library's key names (init_D, init_alpha, w_gen,
// w_prune, penalty, diag_only, update_D, meta, meta_rate, init_lambda, final_lambda, tau_lambda,
// init_S2, add_threshold, kernel, norm_in, norm_out, blend, add_proj, init_n_reg) plus ours
// (max_fields, cutoff, trust_n_data). Unknown keys are errors.
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
