// Validation and expansion of LwprParams.
#include "engine/lwpr/lwpr_params.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm::lwpr {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("LWPR parameter " + what); }

void require_finite(double value, const char* name) {
  if (!std::isfinite(value)) fail(std::string(name) + " must be finite");
}

void require_norm(const Eigen::VectorXd& norm, int dim, const char* name) {
  if (norm.size() != 1 && norm.size() != dim) {
    fail(std::string(name) + " has " + std::to_string(norm.size()) + " elements, expected 1 or " +
         std::to_string(dim));
  }
  for (Eigen::Index i = 0; i < norm.size(); ++i) {
    if (!std::isfinite(norm(i)) || norm(i) <= 0.0) {
      fail(std::string(name) + "[" + std::to_string(i) + "] must be finite and > 0");
    }
  }
}

}  // namespace

void validate_lwpr_params(const LwprParams& p, int n_in, int n_out) {
  if (n_in < 1) fail("n_in must be >= 1");
  if (n_out < 1) fail("n_out must be >= 1");
  if (!p.init_D.allFinite()) fail("init_D must be finite");
  const bool scalar = p.init_D.rows() == 1 && p.init_D.cols() == 1;
  const bool diagonal = p.init_D.rows() == n_in && p.init_D.cols() == 1;
  const bool full = p.init_D.rows() == n_in && p.init_D.cols() == n_in;
  if (!scalar && !diagonal && !full) {
    fail("init_D is " + std::to_string(p.init_D.rows()) + "x" + std::to_string(p.init_D.cols()) +
         ", expected 1x1, " + std::to_string(n_in) + "x1 or " + std::to_string(n_in) + "x" +
         std::to_string(n_in));
  }
  if ((scalar || diagonal) && (p.init_D.array() <= 0.0).any()) fail("init_D must be > 0");
  if (full && n_in > 1) {
    if (!p.init_D.isApprox(p.init_D.transpose(), 1e-12)) fail("init_D must be symmetric");
    Eigen::LLT<Eigen::MatrixXd> llt(p.init_D);
    if (llt.info() != Eigen::Success) fail("init_D must be positive definite");
  } else if (full && p.init_D(0, 0) <= 0.0) {
    fail("init_D must be > 0");
  }
  require_finite(p.init_alpha, "init_alpha");
  if (p.init_alpha <= 0.0) fail("init_alpha must be > 0");
  require_finite(p.penalty, "penalty");
  if (p.penalty < 0.0) fail("penalty must be >= 0");
  require_finite(p.meta_rate, "meta_rate");
  if (p.meta_rate < 0.0) fail("meta_rate must be >= 0");
  if (!(p.w_gen > 0.0 && p.w_gen < 1.0)) fail("w_gen must be in (0, 1)");
  if (!(p.w_prune > 0.0 && p.w_prune <= 1.0)) fail("w_prune must be in (0, 1]");
  for (auto [value, name] : {std::pair{p.init_lambda, "init_lambda"}, std::pair{p.final_lambda, "final_lambda"},
                             std::pair{p.tau_lambda, "tau_lambda"}}) {
    if (!(value > 0.0 && value <= 1.0)) fail(std::string(name) + " must be in (0, 1]");
  }
  require_finite(p.init_S2, "init_S2");
  if (p.init_S2 <= 0.0) fail("init_S2 must be > 0");
  require_finite(p.add_threshold, "add_threshold");
  if (p.add_threshold <= 0.0) fail("add_threshold must be > 0");
  require_norm(p.norm_in, n_in, "norm_in");
  require_norm(p.norm_out, n_out, "norm_out");
  if (p.init_n_reg < 1) fail("init_n_reg must be >= 1");
  if (!(p.cutoff >= 0.0 && p.cutoff < 1.0)) fail("cutoff must be in [0, 1)");
  require_finite(p.trust_n_data, "trust_n_data");
  if (p.trust_n_data < 0.0) fail("trust_n_data must be >= 0");
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
