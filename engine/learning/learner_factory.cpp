#include "engine/learning/learner_factory.hpp"

#include "engine/lwpr/lwpr_model.hpp"

#include <stdexcept>
#include <string>

namespace armfarm {

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
  }
  throw std::invalid_argument("learning.learner: unknown learner");
}

}  // namespace armfarm
