// Validation and expansion of LwprParams.
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/lwpr/lwpr_param_problem.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm::lwpr {
namespace {

ParamProblem problem(std::string name, std::string message) { return {std::move(name), std::nullopt, std::move(message)}; }

std::optional<ParamProblem> check_finite(double value, const char* name) {
  if (!std::isfinite(value)) return problem(name, "must be finite");
  return std::nullopt;
}

std::optional<ParamProblem> check_norm(const Eigen::VectorXd& norm, int dim, const char* name) {
  if (norm.size() != 1 && norm.size() != dim) {
    return problem(name, "has " + std::to_string(norm.size()) + " elements, expected 1 or " + std::to_string(dim));
  }
  for (Eigen::Index i = 0; i < norm.size(); ++i) {
    if (!std::isfinite(norm(i)) || norm(i) <= 0.0) return ParamProblem{name, static_cast<int>(i), "must be finite and > 0"};
  }
  return std::nullopt;
}

std::optional<ParamProblem> check_init_D(const Eigen::MatrixXd& D, int n_in) {
  if (!D.allFinite()) return problem("init_D", "must be finite");
  const bool scalar = D.rows() == 1 && D.cols() == 1;
  const bool diagonal = D.rows() == n_in && D.cols() == 1;
  const bool full = D.rows() == n_in && D.cols() == n_in;
  if (!scalar && !diagonal && !full) {
    return problem("init_D", "is " + std::to_string(D.rows()) + "x" + std::to_string(D.cols()) + ", expected 1x1, " +
                                 std::to_string(n_in) + "x1 or " + std::to_string(n_in) + "x" + std::to_string(n_in));
  }
  if ((scalar || diagonal) && (D.array() <= 0.0).any()) return problem("init_D", "must be > 0");
  if (full && n_in > 1) {
    if (!D.isApprox(D.transpose(), 1e-12)) return problem("init_D", "must be symmetric");
    Eigen::LLT<Eigen::MatrixXd> llt(D);
    if (llt.info() != Eigen::Success) return problem("init_D", "must be positive definite");
  } else if (full && D(0, 0) <= 0.0) {
    return problem("init_D", "must be > 0");
  }
  return std::nullopt;
}

}  // namespace

std::optional<ParamProblem> find_lwpr_param_problem(const LwprParams& p, int n_in, int n_out) {
  if (n_in < 1) return problem("", "n_in must be >= 1");
  if (n_out < 1) return problem("", "n_out must be >= 1");
  if (auto found = check_init_D(p.init_D, n_in)) return found;
  if (auto found = check_finite(p.init_alpha, "init_alpha")) return found;
  if (p.init_alpha <= 0.0) return problem("init_alpha", "must be > 0");
  if (auto found = check_finite(p.penalty, "penalty")) return found;
  if (p.penalty < 0.0) return problem("penalty", "must be >= 0");
  if (auto found = check_finite(p.meta_rate, "meta_rate")) return found;
  if (p.meta_rate < 0.0) return problem("meta_rate", "must be >= 0");
  if (!(p.w_gen > 0.0 && p.w_gen < 1.0)) return problem("w_gen", "must be in (0, 1)");
  if (!(p.w_prune > 0.0 && p.w_prune <= 1.0)) return problem("w_prune", "must be in (0, 1]");
  for (auto [value, name] : {std::pair{p.init_lambda, "init_lambda"}, std::pair{p.final_lambda, "final_lambda"},
                             std::pair{p.tau_lambda, "tau_lambda"}}) {
    if (!(value > 0.0 && value <= 1.0)) return problem(name, "must be in (0, 1]");
  }
  if (auto found = check_finite(p.init_S2, "init_S2")) return found;
  if (p.init_S2 <= 0.0) return problem("init_S2", "must be > 0");
  if (auto found = check_finite(p.add_threshold, "add_threshold")) return found;
  if (p.add_threshold <= 0.0) return problem("add_threshold", "must be > 0");
  if (auto found = check_norm(p.norm_in, n_in, "norm_in")) return found;
  if (auto found = check_norm(p.norm_out, n_out, "norm_out")) return found;
  if (p.init_n_reg < 1) return problem("init_n_reg", "must be >= 1");
  if (!(p.cutoff >= 0.0 && p.cutoff < 1.0)) return problem("cutoff", "must be in [0, 1)");
  if (auto found = check_finite(p.trust_n_data, "trust_n_data")) return found;
  if (p.trust_n_data < 0.0) return problem("trust_n_data", "must be >= 0");
  return std::nullopt;
}

void validate_lwpr_params(const LwprParams& p, int n_in, int n_out) {
  if (const std::optional<ParamProblem> found = find_lwpr_param_problem(p, n_in, n_out)) {
    throw std::invalid_argument("LWPR parameter " + found->describe());
  }
}

Eigen::MatrixXd calc_init_metric(const LwprParams& p, int n_in) {
  if (p.init_D.rows() == 1 && p.init_D.cols() == 1) {
    return p.init_D(0, 0) * Eigen::MatrixXd::Identity(n_in, n_in);
  }
  if (p.init_D.cols() == 1) return p.init_D.col(0).asDiagonal();
  return p.init_D;
}

Eigen::VectorXd calc_norm_vector(const Eigen::VectorXd& norm, int dim) {
  if (norm.size() == 1) return Eigen::VectorXd::Constant(dim, norm(0));
  return norm;
}

}  // namespace armfarm::lwpr
