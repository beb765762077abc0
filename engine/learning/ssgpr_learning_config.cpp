#include "engine/learning/ssgpr_learning_config.hpp"

namespace armfarm {

ssgpr::SsgprParams make_job_ssgpr_defaults() {
  ssgpr::SsgprParams params;
  params.features = 200;
  params.lengthscales = Eigen::VectorXd::Constant(1, 2.0);
  return params;
}

const std::vector<ConfigKey<SsgprLearningConfig>>& ssgpr_learning_config_keys() {
  using C = SsgprLearningConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"features", "", closed(1, 2000), ListSize::any, "D, random Fourier frequencies (2D features); cost O(D²) per update",
       [](C& c) { return make_integer_field(c.params.features); }},
      {"lengthscales", "", left_open(0.0, 1e6), ListSize::lwpr_inputs,
       "squared-exponential lengthscales: one for all or one per input (q, q̇, q̈ of each active joint), in input stds when "
       "normalize_inputs; the fit's start when fit_samples > 0",
       [](C& c) { return make_field(c.params.lengthscales, ValueKind::real_or_list); }},
      {"signal_variance", "", left_open(0.0, 1e6), ListSize::any, "σ_f², the kernel's variance in output_scale² units (fitted when fit_samples > 0)",
       [](C& c) { return make_field(c.params.signal_variance); }},
      {"noise_variance", "", left_open(0.0, 1e6), ListSize::any, "σ_n², the noise variance in output_scale² units (fitted when fit_samples > 0)",
       [](C& c) { return make_field(c.params.noise_variance); }},
      {"output_scale", "N·m", left_open(0.0, 1e6), ListSize::lwpr_outputs,
       "the model learns torque / this: one for all or one per active joint (the RMS torque when fitted with fit_output_scale)",
       [](C& c) { return make_field(c.params.output_scale, ValueKind::real_or_list); }},
      {"forgetting", "", left_open(0.0, 1.0), ListSize::any, "λ: past samples weigh λ^age (exponentially weighted); 1 = no forgetting",
       [](C& c) { return make_field(c.params.forgetting); }},
      {"seed", "", closed(0, 9.2e18), ListSize::any, "seed of the frequency draw (stream \"ssgpr.features\"), apart from the job's seed",
       [](C& c) { return make_integer_field(c.params.seed); }},
      {"trust_min_samples", "", closed(0, 1e9), ListSize::any, "samples learnt before the learner may predict",
       [](C& c) { return make_integer_field(c.params.trust_min_samples); }},
      {"trust_variance_fraction", "", closed(0.0, 1.0), ListSize::any,
       "predict only where the posterior latent variance is at most this fraction of σ_f² (1 = samples alone decide)",
       [](C& c) { return make_field(c.params.trust_variance_fraction); }},
      {"resolve_interval", "", closed(0, 1e9), ListSize::any, "re-solve the weights from scratch every this many updates (0 = never)",
       [](C& c) { return make_integer_field(c.params.resolve_interval); }},
      {"fit_samples", "", closed(0, 3000), ListSize::any,
       "fit the hyperparameters on the first this many samples (untrusted until then); 0 = use them as given",
       [](C& c) { return make_integer_field(c.fit_samples); }},
      {"fit_iterations", "", closed(1, 1000), ListSize::any, "iRprop− steps of the hyperparameter fit (each O(fit_samples³))",
       [](C& c) { return make_integer_field(c.fit.iterations); }},
      {"fit_output_scale", "", {}, ListSize::any, "the fit first sets output_scale to each torque's RMS over the fit samples",
       [](C& c) { return make_field(c.fit.fit_output_scale); }},
  };
  return keys;
}

}  // namespace armfarm
