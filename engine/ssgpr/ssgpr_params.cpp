// Validation of SsgprParams.
#include "engine/ssgpr/ssgpr_params.hpp"
#include "engine/ssgpr/ssgpr_param_problem.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm::ssgpr {
namespace {

ParamProblem problem(std::string name, std::string message) { return {std::move(name), std::nullopt, std::move(message)}; }

std::optional<ParamProblem> check_positive_vector(const Eigen::VectorXd& v, int dim, const char* name) {
  if (v.size() != 1 && v.size() != dim) {
    return problem(name, "has " + std::to_string(v.size()) + " elements, expected 1 or " + std::to_string(dim));
  }
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v(i)) || v(i) <= 0.0) return ParamProblem{name, static_cast<int>(i), "must be finite and > 0"};
  }
  return std::nullopt;
}

std::optional<ParamProblem> check_positive(double v, const char* name) {
  if (!std::isfinite(v) || v <= 0.0) return problem(name, "must be finite and > 0");
  return std::nullopt;
}

}  // namespace

std::optional<ParamProblem> find_ssgpr_param_problem(const SsgprParams& params, int n_in, int n_out) {
  if (n_in < 1 || n_out < 1) return problem("", "sizes: n_in and n_out must be >= 1");
  if (params.features < 1 || params.features > (1 << 15)) return problem("features", "must be in [1, 32768]");
  if (auto found = check_positive_vector(params.lengthscales, n_in, "lengthscales")) return found;
  if (auto found = check_positive_vector(params.output_scale, n_out, "output_scale")) return found;
  if (auto found = check_positive(params.signal_variance, "signal_variance")) return found;
  if (auto found = check_positive(params.noise_variance, "noise_variance")) return found;
  if (!(params.forgetting > 0.0 && params.forgetting <= 1.0)) return problem("forgetting", "must be in (0, 1]");
  if (!(params.trust_variance_fraction >= 0.0 && params.trust_variance_fraction <= 1.0)) {
    return problem("trust_variance_fraction", "must be in [0, 1]");
  }
  return std::nullopt;
}

void validate_ssgpr_params(const SsgprParams& params, int n_in, int n_out) {
  if (const std::optional<ParamProblem> found = find_ssgpr_param_problem(params, n_in, n_out)) {
    throw std::invalid_argument("SSGPR parameter " + found->describe());
  }
}

Eigen::VectorXd calc_expanded_vector(const Eigen::VectorXd& v, int dim) {
  return v.size() == 1 ? Eigen::VectorXd::Constant(dim, v(0)) : v;
}

}  // namespace armfarm::ssgpr
