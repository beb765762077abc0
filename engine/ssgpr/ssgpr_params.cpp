// Validation of SsgprParams.
#include "engine/ssgpr/ssgpr_params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm::ssgpr {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("SSGPR parameter " + what); }

void check_positive_vector(const Eigen::VectorXd& v, int dim, const char* name) {
  if (v.size() != 1 && v.size() != dim) {
    fail(std::string(name) + " has " + std::to_string(v.size()) + " elements, expected 1 or " + std::to_string(dim));
  }
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v(i)) || v(i) <= 0.0) fail(std::string(name) + "[" + std::to_string(i) + "] must be finite and > 0");
  }
}

void check_positive(double v, const char* name) {
  if (!std::isfinite(v) || v <= 0.0) fail(std::string(name) + " must be finite and > 0");
}

}  // namespace

void validate_ssgpr_params(const SsgprParams& params, int n_in, int n_out) {
  if (n_in < 1 || n_out < 1) fail("sizes: n_in and n_out must be >= 1");
  if (params.features < 1 || params.features > (1 << 15)) fail("features must be in [1, 32768]");
  check_positive_vector(params.lengthscales, n_in, "lengthscales");
  check_positive_vector(params.output_scale, n_out, "output_scale");
  check_positive(params.signal_variance, "signal_variance");
  check_positive(params.noise_variance, "noise_variance");
  if (!(params.forgetting > 0.0 && params.forgetting <= 1.0)) fail("forgetting must be in (0, 1]");
  if (!(params.trust_variance_fraction >= 0.0 && params.trust_variance_fraction <= 1.0)) {
    fail("trust_variance_fraction must be in [0, 1]");
  }
}

Eigen::VectorXd calc_expanded_vector(const Eigen::VectorXd& v, int dim) {
  return v.size() == 1 ? Eigen::VectorXd::Constant(dim, v(0)) : v;
}

}  // namespace armfarm::ssgpr
