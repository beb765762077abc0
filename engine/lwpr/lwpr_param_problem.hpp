#pragma once
// LWPR's parameter check as a value (engine/learner/param_problem.hpp): what
// validate_lwpr_params (lwpr_params.hpp) throws for, found without an exception, so that the
// job validation reports it at its key path (learning.lwpr.init_D) without reading error text.
#include "engine/learner/param_problem.hpp"
#include "engine/lwpr/lwpr_params.hpp"

#include <optional>

namespace armfarm::lwpr {

/// The first problem that makes `params` unusable for a model with n_in inputs and n_out outputs
/// (wrong sizes, non-finite or out-of-range values, D not SPD); nullopt when usable.
/// validate_lwpr_params throws std::invalid_argument("LWPR parameter " + problem.describe()).
std::optional<ParamProblem> find_lwpr_param_problem(const LwprParams& params, int n_in, int n_out);

}  // namespace armfarm::lwpr
