#include "engine/learning/learner_factory.hpp"

#include "engine/lwpr/lwpr_model.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// "SSGPR parameter lengthscales has ..." → "lengthscales has ..." (the caller adds the path).
std::string strip_prefix(const std::string& message, const std::string& prefix) {
  return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

std::unique_ptr<Learner> make_ssgpr(const SsgprLearningConfig& config, int n_in, int n_out, const Eigen::VectorXd& input_scale) {
  ssgpr::SsgprParams params = config.params;
  try {
    // Lengthscales given in input standard deviations become the inputs' own units.
    if (input_scale.size()) {
      ssgpr::validate_ssgpr_params(params, n_in, n_out);
      params.lengthscales = ssgpr::calc_expanded_vector(params.lengthscales, n_in).cwiseProduct(input_scale);
    }
    if (config.fit_samples == 0) return std::make_unique<ssgpr::SsgprModel>(n_in, n_out, params);
    return std::make_unique<ssgpr::SsgprFittingLearner>(n_in, n_out, params, config.fit_samples, config.fit);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("learning.ssgpr: " + strip_prefix(error.what(), "SSGPR parameter "));
  }
}

}  // namespace

std::unique_ptr<Learner> make_learner(const LearningConfig& config, int n_in, int n_out, const Eigen::VectorXd& input_scale) {
  switch (config.learner) {
    case LearnerKind::lwpr: {
      lwpr::LwprParams params = config.lwpr;
      if (input_scale.size()) params.norm_in = input_scale;
      try {
        return std::make_unique<lwpr::LwprModel>(n_in, n_out, params);
      } catch (const std::invalid_argument& error) {
        throw std::invalid_argument(std::string("learning.lwpr: ") + error.what());
      }
    }
    case LearnerKind::ssgpr:
      return make_ssgpr(config.ssgpr, n_in, n_out, input_scale);
  }
  throw std::invalid_argument("learning.learner: unknown learner");
}

}  // namespace armfarm
