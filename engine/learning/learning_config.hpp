#pragma once
// How a job learns its inverse dynamics: the learning mode, the batch schedule and the LWPR
// parameters it starts from, with the only copy of the job's defaults, and the key tables
// (engine/config/config_key.hpp) of LearningConfig and of LWPR's parameter block.
//
// Two defaults of init_D, on purpose, one home each:
//  - lwpr::LwprParams{} (engine/lwpr/lwpr_params.hpp) keeps the published library's defaults
//    (init_D = 25·I), what `armfarm lwpr fit` uses on raw, unnormalised data;
//  - a job starts from make_job_lwpr_defaults() (init_D = 0.05·I on inputs normalised to unit
//    standard deviation, trust_n_data = 5), the default of LearningConfig::lwpr; the JSON
//    defaults and the documentation are written from it.
#include "engine/config/config_key.hpp"
#include "engine/lwpr/lwpr_params.hpp"

#include <vector>

namespace armfarm {

enum class LearningMode {
  none,    ///< no learner (feedback, or analytic feed-forward)
  online,  ///< learn every tick while controlling with the learner's prediction
  batch,   ///< collect under feedback, train offline, then control with the frozen model
};
const EnumNames& learning_mode_names();

/// The LWPR parameters a job starts from: the published defaults except init_D = 0.05·I (on
/// inputs normalised to unit standard deviation, see normalize_inputs) and trust_n_data = 5,
/// measured on the default sinusoid (sweeps/README.md gives the figures).
lwpr::LwprParams make_job_lwpr_defaults();

struct LearningConfig {
  LearningMode mode = LearningMode::online;
  lwpr::LwprParams lwpr = make_job_lwpr_defaults();  ///< inputs (q, q̇, q̈) of the active joints, outputs their torques
  bool learn_during_evaluation = false;  ///< batch: keep updating the model while it controls
  double train_fraction = 0.75;      ///< batch: share of the collected samples used for training
  int epochs = 5;                    ///< batch: passes over the (shuffled) training samples
  int collect_repeats = 2;           ///< batch: trajectory repeats collected under feedback
  /// Batch: the gain scale of the feedback controller that collects the samples (the learned
  /// model then drives the evaluation run at control.gain_scale).
  double collect_gain_scale = 1.0;
  /// Replace lwpr.norm_in by each input's standard deviation along the desired trajectory
  /// (q, q̇, q̈ differ by orders of magnitude; one kernel width cannot suit all three raw).
  bool normalize_inputs = true;
};

/// LearningConfig's own keys (mode, batch schedule); the LWPR block is lwpr_params_keys().
const std::vector<ConfigKey<LearningConfig>>& learning_config_keys();

/// lwpr::Kernel's spellings ("gaussian", "bisquare").
const EnumNames& lwpr_kernel_names();

/// LWPR's parameter block with the published library's key names, units "" (the parameters
/// act on normalised inputs and outputs) and the ranges validate() checks; shapes of init_D,
/// norm_in and norm_out are checked by lwpr::validate_lwpr_params.
const std::vector<ConfigKey<lwpr::LwprParams>>& lwpr_params_keys();

}  // namespace armfarm
