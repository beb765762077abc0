#include "engine/learning/learning_config.hpp"

namespace armfarm {

const EnumNames& learning_mode_names() {
  static const EnumNames names = {
      {"none", static_cast<int>(LearningMode::none), "no learner"},
      {"online", static_cast<int>(LearningMode::online), "learn every tick while controlling"},
      {"batch", static_cast<int>(LearningMode::batch), "collect under feedback, train, then control with the frozen model"},
      {"frozen", static_cast<int>(LearningMode::frozen), "control with learning.initial_model's predictions, never updating it"},
  };
  return names;
}

const EnumNames& learner_kind_names() {
  static const EnumNames names = {
      {"lwpr", static_cast<int>(LearnerKind::lwpr), "locally weighted projection regression"},
      {"ssgpr", static_cast<int>(LearnerKind::ssgpr), "incremental sparse-spectrum Gaussian-process regression"},
  };
  return names;
}

lwpr::LwprParams make_job_lwpr_defaults() {
  lwpr::LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 0.05);
  params.trust_n_data = 5.0;
  params.loo_start = lwpr::LooStart::kEarly;
  return params;
}

const std::vector<ConfigKey<LearningConfig>>& learning_config_keys() {
  using C = LearningConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"mode", "", {}, ListSize::any, "online (learn every tick), batch (collect under feedback, train, then control), frozen (control with learning.initial_model, never learning) or none",
       [](C& c) { return make_choice_field(c.mode, learning_mode_names()); }},
      {"normalize_inputs", "", {}, ListSize::any,
       "divide each input by its standard deviation along the desired trajectory (replaces lwpr.norm_in)",
       [](C& c) { return make_field(c.normalize_inputs); }},
      {"train_fraction", "", left_open(0.0, 1.0), ListSize::any, "batch: share of the collected samples used for training",
       [](C& c) { return make_field(c.train_fraction); }},
      {"epochs", "", closed(1, 1000), ListSize::any, "batch: passes over the shuffled training samples",
       [](C& c) { return make_integer_field(c.epochs); }},
      {"collect_repeats", "", closed(1, 1000), ListSize::any, "batch: trajectory passes collected under feedback",
       [](C& c) { return make_integer_field(c.collect_repeats); }},
      {"collect_gain_scale", "", closed(0.0, 100.0), ListSize::any, "gain scale of the feedback controller while collecting (batch collection, the held-out set); \"auto\" = control.gain_scale, the job's own gains",
       [](C& c) { return make_field(c.collect_gain_scale); }},
      {"learn_during_evaluation", "", {}, ListSize::any, "batch: keep learning while the learned model controls",
       [](C& c) { return make_field(c.learn_during_evaluation); }},
      {"learner", "", {}, ListSize::any, "lwpr (parameters learning.lwpr.*) or ssgpr (learning.ssgpr.*)",
       [](C& c) { return make_choice_field(c.learner, learner_kind_names()); }},
      {"collect_repeat_noise_q", "rad", closed(0.0, 1.0), ListSize::any,
       "batch: repeats after the first measure the angles with sensor noise of this std (on top of collect_noise_q; 0 and no start spread = exact copies)",
       [](C& c) { return make_field(c.collect_repeat_noise_q); }},
      {"collect_start_spread", "rad", closed(0.0, 1.0), ListSize::any,
       "batch: repeats after the first start off the trajectory by a seeded normal draw of this std per joint (start transients in both sets)",
       [](C& c) { return make_field(c.collect_start_spread); }},
      {"collect_noise_q", "rad", closed(0.0, 1.0), ListSize::any, "std of the sensor noise on the measured angles while collecting",
       [](C& c) { return make_field(c.collect_noise_q); }},
      {"collect_noise_qd", "rad/s", closed(0.0, 10.0), ListSize::any,
       "std of the sensor noise on the measured velocities while collecting", [](C& c) { return make_field(c.collect_noise_qd); }},
      {"heldout", "", {}, ListSize::any, "score the frozen learner on a held-out realisation of the trajectory (heldout_* metrics)",
       [](C& c) { return make_field(c.heldout); }},
      {"heldout_checkpoints", "", closed(0, 1e9), ListSize::any,
       "increasing; online: after this many completed segments (0 = before learning); batch: after this many epochs; "
       "[] = once at the end",
       [](C& c) { return make_field(c.heldout_checkpoints); }},
      {"heldout_segments", "", closed(0, 100000), ListSize::any,
       "held-out trajectory length in reaches, periods or loops; 0 = 9 reaches or 1 period / loop",
       [](C& c) { return make_integer_field(c.heldout_segments); }},
      {"heldout_amplitude_scale", "", open(0.0, 10.0), ListSize::any,
       "held-out variant: sine amplitudes and the figure-eight's scale × this", [](C& c) { return make_field(c.heldout_amplitude_scale); }},
      {"heldout_phase_step", "rad", closed(-10.0, 10.0), ListSize::any, "held-out sine: joint i's phase + (i − 1) × this",
       [](C& c) { return make_field(c.heldout_phase_step); }},
      {"heldout_recorded_fraction", "", open(0.0, 1.0), ListSize::any,
       "recorded motion: the last fraction of the recording is held out and never replayed while learning",
       [](C& c) { return make_field(c.heldout_recorded_fraction); }},
      {"store_model", "", {}, ListSize::any, "store the learner's model file, as it is at the end of the job, in the results database",
       [](C& c) { return make_field(c.store_model); }},
      {"initial_model", "", {}, ListSize::any,
       "start the learner from this model (a model file, or a stored model: {\"job\": KEY} or {\"sweep\": NAME, \"params\": {...}}); \"\" = untrained",
       [](C& c) { return make_field(c.initial_model); }},
  };
  return keys;
}

const EnumNames& lwpr_kernel_names() {
  static const EnumNames names = {
      {"gaussian", static_cast<int>(lwpr::Kernel::kGaussian), "w = exp(−q/2)"},
      {"bisquare", static_cast<int>(lwpr::Kernel::kBisquare), "w = (1 − q/4)² for q < 4"},
  };
  return names;
}

const EnumNames& lwpr_loo_start_names() {
  static const EnumNames names = {
      {"library", static_cast<int>(lwpr::LooStart::kLibrary), "once n_data > 0.1/(1−λ), as the published library"},
      {"early", static_cast<int>(lwpr::LooStart::kEarly), "once n_data > min(0.1/(1−λ), 4·(R+1))"},
  };
  return names;
}

const std::vector<ConfigKey<lwpr::LwprParams>>& lwpr_params_keys() {
  using P = lwpr::LwprParams;
  static const std::vector<ConfigKey<P>> keys = {
      {"init_D", "", left_open(0.0, 1e6), ListSize::any,
       "initial distance metric of a new field: a number (·I), a list (diagonal) or a list of lists (full, SPD)",
       [](P& p) { return make_field(p.init_D); }},
      {"init_alpha", "", left_open(0.0, 1e6), ListSize::any, "initial learning rate of the distance metric",
       [](P& p) { return make_field(p.init_alpha); }},
      {"penalty", "", closed(0.0, 1.0), ListSize::any, "penalty γ on large D in the PRESS cost; larger → wider fields",
       [](P& p) { return make_field(p.penalty); }},
      {"diag_only", "", {}, ListSize::any, "adapt only the diagonal of D", [](P& p) { return make_field(p.diag_only); }},
      {"update_D", "", {}, ListSize::any, "adapt D by gradient descent on the PRESS cost", [](P& p) { return make_field(p.update_D); }},
      {"meta", "", {}, ListSize::any, "second-order (IDBD) adaptation of D's learning rates", [](P& p) { return make_field(p.meta); }},
      {"meta_rate", "", closed(0.0, 1e6), ListSize::any, "IDBD meta learning rate", [](P& p) { return make_field(p.meta_rate); }},
      {"w_gen", "", open(0.0, 1.0), ListSize::any, "a new field is created when no field is activated more than this",
       [](P& p) { return make_field(p.w_gen); }},
      {"w_prune", "", left_open(0.0, 1.0), ListSize::any, "of two fields activated more than this the wider is pruned; 1 never prunes",
       [](P& p) { return make_field(p.w_prune); }},
      {"init_lambda", "", left_open(0.0, 1.0), ListSize::any, "initial forgetting factor", [](P& p) { return make_field(p.init_lambda); }},
      {"final_lambda", "", left_open(0.0, 1.0), ListSize::any, "final forgetting factor", [](P& p) { return make_field(p.final_lambda); }},
      {"tau_lambda", "", left_open(0.0, 1.0), ListSize::any, "annealing rate of the forgetting factor",
       [](P& p) { return make_field(p.tau_lambda); }},
      {"init_S2", "", left_open(0.0, 1e6), ListSize::any, "initial weighted variance of a projection",
       [](P& p) { return make_field(p.init_S2); }},
      {"add_threshold", "", left_open(0.0, 10.0), ListSize::any, "add a projection when the MSE ratio of R over R−1 is below this",
       [](P& p) { return make_field(p.add_threshold); }},
      {"kernel", "", {}, ListSize::any, "gaussian or bisquare", [](P& p) { return make_choice_field(p.kernel, lwpr_kernel_names()); }},
      {"norm_in", "", left_open(0.0, 1e12), ListSize::lwpr_inputs,
       "input scales: one for all or one per input (q, q̇, q̈ of each active joint); replaced when normalize_inputs",
       [](P& p) { return make_field(p.norm_in, ValueKind::real_or_list); }},
      {"norm_out", "", left_open(0.0, 1e12), ListSize::lwpr_outputs, "output scales: one for all or one per active joint",
       [](P& p) { return make_field(p.norm_out, ValueKind::real_or_list); }},
      {"blend", "", {}, ListSize::any, "blend all active fields' predictions (else the most active one)",
       [](P& p) { return make_field(p.blend); }},
      {"add_proj", "", {}, ListSize::any, "allow projections beyond init_n_reg", [](P& p) { return make_field(p.add_proj); }},
      {"init_n_reg", "", closed(1, 100), ListSize::any, "PLS projections a new field starts with",
       [](P& p) { return make_integer_field(p.init_n_reg); }},
      {"max_fields", "", closed(0, 1e6), ListSize::any, "most receptive fields per output; 0 = unlimited",
       [](P& p) { return make_integer_field(p.max_fields); }},
      {"cutoff", "", right_open(0.0, 1.0), ListSize::any, "fields activated at most this much are neither updated nor used",
       [](P& p) { return make_field(p.cutoff); }},
      {"trust_n_data", "", closed(0.0, 1e9), ListSize::any, "samples a field must have seen (counted with forgetting) before it may predict; 0 = 2·n_in",
       [](P& p) { return make_field(p.trust_n_data); }},
      {"loo_start", "", {}, ListSize::any,
       "when a field starts its leave-one-out statistics and metric learning: library (n_data > 0.1/(1−λ)) or early (also after 4·(R+1) samples)",
       [](P& p) { return make_choice_field(p.loo_start, lwpr_loo_start_names()); }},
  };
  return keys;
}

}  // namespace armfarm
