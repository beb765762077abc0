#pragma once
// How a job's SSGPR learner (engine/ssgpr/, selected by learning.learner = "ssgpr") is set up:
// the model's parameters and the hyperparameter fit on its first samples, with the job's
// defaults (the only copy) and the key table of the learning.ssgpr block
// (engine/config/config_key.hpp). With learning.normalize_inputs the lengthscales are in units
// of each input's standard deviation along the desired trajectory (the factory multiplies them
// by it); without it, in the inputs' own units (rad, rad/s, rad/s²).
#include "engine/config/config_key.hpp"
#include "engine/ssgpr/ssgpr_fit.hpp"
#include "engine/ssgpr/ssgpr_params.hpp"

#include <cstddef>
#include <vector>

namespace armfarm {

/// SsgprParams{} except lengthscales = 2 (input standard deviations: the fit's start) and
/// 200 features; see SsgprLearningConfig for why the variances need no job default.
ssgpr::SsgprParams make_job_ssgpr_defaults();

struct SsgprLearningConfig {
  /// Inputs (q, q̇, q̈) of the active joints, outputs their torques. signal_variance,
  /// noise_variance are in units of output_scale² (output_scale in N·m); with fit_samples > 0
  /// and fit_output_scale they, the lengthscales and output_scale are replaced by the fit.
  ssgpr::SsgprParams params = make_job_ssgpr_defaults();
  /// > 0: the learner keeps its first fit_samples samples (predicting nothing, all untrusted),
  /// then fits lengthscales, σ_f², σ_n² (and output_scale) to them by the GP marginal likelihood
  /// (engine/ssgpr/ssgpr_fit.hpp, iRprop−, O(fit_samples³) per iteration), builds the model and
  /// learns those samples; 0: the model starts at once with the parameters as given.
  std::size_t fit_samples = 300;
  /// iterations and fit_output_scale are used; max_samples is set to fit_samples.
  ssgpr::SsgprFitConfig fit;
};

/// The learning.ssgpr keys (SsgprParams' field names, plus fit_samples, fit_iterations,
/// fit_output_scale), ranges checked by validate(); sizes of lengthscales (1 or 3 × active
/// joints) and output_scale (1 or one per active joint) by the list rules.
const std::vector<ConfigKey<SsgprLearningConfig>>& ssgpr_learning_config_keys();

}  // namespace armfarm
