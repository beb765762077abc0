#pragma once
// The one place a job's learner is made from its learning configuration. The experiment flow
// sees only the Learner interface, so another learner is a new LearnerKind and a new case here,
// with no change to the flow.
#include "engine/learning/learning_config.hpp"
#include "engine/learner/learner.hpp"

#include <Eigen/Core>

#include <memory>

namespace armfarm {

/// An untrained learner of n_in → n_out as `config.learner` says. `input_scale` (n_in, or empty
/// for none) is a typical magnitude per input (the job passes each input's standard deviation
/// along the desired trajectory when normalize_inputs is on); LWPR divides its inputs by it,
/// SSGPR multiplies its lengthscales by it. SSGPR with ssgpr.fit_samples > 0 is an
/// ssgpr::SsgprFittingLearner (fits its hyperparameters on its first samples), else an
/// ssgpr::SsgprModel. Throws std::invalid_argument starting with the configuration path
/// ("learning.lwpr: ...", "learning.ssgpr: ...").
std::unique_ptr<Learner> make_learner(const LearningConfig& config, int n_in, int n_out, const Eigen::VectorXd& input_scale);

}  // namespace armfarm
