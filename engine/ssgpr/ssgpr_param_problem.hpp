#pragma once
// SSGPR's parameter check as a value (engine/learner/param_problem.hpp): what
// validate_ssgpr_params (ssgpr_params.hpp) throws for, found without an exception, so that the
// job validation reports it at its key path (learning.ssgpr.lengthscales[2]) without reading
// error text.
#include "engine/learner/param_problem.hpp"
#include "engine/ssgpr/ssgpr_params.hpp"

#include <optional>

namespace armfarm::ssgpr {

/// The first problem that makes `params` unusable for n_in inputs and n_out outputs (sizes,
/// non-finite or out-of-range values); nullopt when usable. validate_ssgpr_params throws
/// std::invalid_argument("SSGPR parameter " + problem.describe()).
std::optional<ParamProblem> find_ssgpr_param_problem(const SsgprParams& params, int n_in, int n_out);

}  // namespace armfarm::ssgpr
