#include "engine/learning/learner_factory.hpp"

#include "engine/lwpr/lwpr_model.hpp"
#include "engine/ssgpr/ssgpr_param_problem.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

#include <optional>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

// Throws std::invalid_argument "learning.<block>: <problem>" for a parameter problem (the
// runner's validate() reports these first, with their key paths).
void require_no_problem(const std::optional<ParamProblem>& problem, const char* block) {
  if (problem) throw std::invalid_argument(std::string(block) + ": " + problem->describe());
}

std::unique_ptr<Learner> make_ssgpr(const SsgprLearningConfig& config, int n_in, int n_out, const Eigen::VectorXd& input_scale) {
  ssgpr::SsgprParams params = config.params;
  require_no_problem(ssgpr::find_ssgpr_param_problem(params, n_in, n_out), "learning.ssgpr");
  // Lengthscales given in input standard deviations become the inputs' own units.
  if (input_scale.size()) {
    params.lengthscales = ssgpr::calc_expanded_vector(params.lengthscales, n_in).cwiseProduct(input_scale);
    require_no_problem(ssgpr::find_ssgpr_param_problem(params, n_in, n_out), "learning.ssgpr");  // a joint that never moves
  }
  try {
    if (config.fit_samples == 0) return std::make_unique<ssgpr::SsgprModel>(n_in, n_out, params);
    return std::make_unique<ssgpr::SsgprFittingLearner>(n_in, n_out, params, config.fit_samples, config.fit);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("learning.ssgpr: ") + error.what());
  }
}

}  // namespace

std::unique_ptr<Learner> make_learner(const LearningConfig& config, int n_in, int n_out, const Eigen::VectorXd& input_scale) {
  switch (config.learner) {
    case LearnerKind::lwpr: {
      lwpr::LwprParams params = config.lwpr;
      if (input_scale.size()) params.norm_in = input_scale;
      try {
        return std::make_unique<lwpr::LwprModel>(n_in, n_out, params);  // checks its parameters (its own precondition)
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
