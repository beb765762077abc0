#pragma once
// How a job learns its inverse dynamics: the learning mode, the batch schedule and the LWPR
// parameters it starts from, with the only copy of the job's defaults, and the key tables
// (engine/config/config_key.hpp) of LearningConfig and of LWPR's parameter block (SSGPR's
// block: engine/learning/ssgpr_learning_config.hpp).
//
// Two defaults of init_D, on purpose, one home each:
//  - lwpr::LwprParams{} (engine/lwpr/lwpr_params.hpp) keeps the published library's defaults
//    (init_D = 25·I), what `armfarm lwpr fit` uses on raw, unnormalised data;
//  - a job starts from make_job_lwpr_defaults() (init_D = 0.05·I on inputs normalised to unit
//    standard deviation, trust_n_data = 5, loo_start "early"), the default of LearningConfig::lwpr; the JSON
//    defaults and the documentation are written from it.
#include "engine/config/config_key.hpp"
#include "engine/learning/ssgpr_learning_config.hpp"
#include "engine/lwpr/lwpr_params.hpp"

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

enum class LearningMode {
  none,    ///< no learner (feedback, or analytic feed-forward)
  online,  ///< learn every tick while controlling with the learner's prediction
  batch,   ///< collect under feedback, train offline, then control with the frozen model
  frozen,  ///< control with the predictions of learning.initial_model, never updating it (a test stage)
};
const EnumNames& learning_mode_names();

/// The learners the factory (engine/learning/learner_factory.hpp) knows; another one is a new
/// enumerator, a spelling in learner_kind_names() and a case in the factory.
enum class LearnerKind {
  lwpr,   ///< locally weighted projection regression (engine/lwpr/), block learning.lwpr
  ssgpr,  ///< incremental sparse-spectrum GP regression (engine/ssgpr/), block learning.ssgpr
};
const EnumNames& learner_kind_names();

/// The LWPR parameters a job starts from: the published defaults except init_D = 0.05·I (on
/// inputs normalised to unit standard deviation, see normalize_inputs) and trust_n_data = 5,
/// measured on the default sinusoid (sweeps/README.md gives the figures), and loo_start "early"
/// (the online reaching job's feedback; engine/lwpr/README.md, "Start rule").
lwpr::LwprParams make_job_lwpr_defaults();

struct LearningConfig {
  LearningMode mode = LearningMode::online;
  lwpr::LwprParams lwpr = make_job_lwpr_defaults();  ///< inputs (q, q̇, q̈) of the active joints, outputs their torques
  bool learn_during_evaluation = false;  ///< batch: keep updating the model while it controls
  double train_fraction = 0.75;      ///< batch: share of the collected samples used for training
  int epochs = 5;                    ///< batch: passes over the (shuffled) training samples
  int collect_repeats = 2;           ///< batch: trajectory repeats collected under feedback
  /// The gain scale of the feedback controller that collects samples (batch collection and the
  /// held-out set; the learned model then drives the evaluation run at control.gain_scale).
  /// Empty ("auto"): control.gain_scale, the job's own gains (kd scaled per keep_damping_ratio).
  std::optional<double> collect_gain_scale;
  /// Replace lwpr.norm_in by each input's standard deviation along the desired trajectory
  /// (q, q̇, q̈ differ by orders of magnitude; one kernel width cannot suit all three raw).
  bool normalize_inputs = true;
  /// Which learner the factory builds.
  LearnerKind learner = LearnerKind::lwpr;
  /// SSGPR's block (used when learner is ssgpr; engine/learning/ssgpr_learning_config.hpp).
  SsgprLearningConfig ssgpr;

  /// Batch: every collection repeat after the first measures its joint angles with sensor noise
  /// of this standard deviation (rad, on top of collect_noise_q; stream "collection.sensor_noise"),
  /// so a repeat is a different realisation of the run all along, never a copy, and starts on the
  /// trajectory (no start transient for a same-run split to score; sweeps/thesis/README.md,
  /// "Collection"). The collecting controller and the collected samples see the measured angles.
  double collect_repeat_noise_q = 1e-3;
  /// Batch: every collection repeat after the first starts off the trajectory by a seeded
  /// normal draw of this standard deviation per joint angle (rad; stream "collection.start_state").
  /// 0 (default): on the trajectory. A spread puts start transients into both sets.
  double collect_start_spread = 0.0;
  /// Standard deviation of the sensor noise on the measured q (rad) and q̇ (rad/s) that the
  /// collecting controller and the collected samples see (every pass of the batch and held-out collections).
  double collect_noise_q = 0.0;
  double collect_noise_qd = 0.0;

  /// Held-out evaluation (online and batch): the learner, frozen, is scored on a different
  /// realisation of the trajectory it never trained on (heldout_* metrics;
  /// engine/experiment/heldout_evaluation.hpp).
  bool heldout = true;
  /// When to evaluate: online, after this many completed segments of the learning pass (reaches
  /// for reaching, periods of the slowest joint for sine, loops for figure-eight and recorded;
  /// 0 = before learning); batch, after this many training epochs. Increasing. Empty: once, at the end.
  std::vector<int> heldout_checkpoints;
  /// Segments of the held-out trajectory (reaches, periods, loops); 0: 9 reaches (the thesis's
  /// 9 held-out transitions), otherwise 1 period or loop. Ignored for recorded motion.
  int heldout_segments = 0;
  /// Sine and figure-eight: the held-out variant's amplitude (figure-eight: scale) relative to
  /// the training trajectory's.
  double heldout_amplitude_scale = 0.8;
  /// Sine: the held-out variant adds (i − 1)·this phase (rad) to the i-th active joint (relative
  /// phases change, so the joint-space path differs, not just its start time).
  double heldout_phase_step = 0.785398163397448;  // π/4
  /// Recorded motion: the last fraction of the recording is held out and never trained on (the
  /// learning pass replays the rest).
  double heldout_recorded_fraction = 0.25;

  /// Return the trained learner's model file in the job's outcome (JobOutcome::model_file; the
  /// runner stores it in the results database), as it is at the end of the job.
  bool store_model = false;
  /// The model the job's learner starts from instead of an untrained one, as the configuration
  /// names it (a model file path, or "stored:xxh3-128:<hash>" once the runner resolved a stored
  /// model); empty: an untrained learner from `learner` and `lwpr`. The runner reads it into
  /// initial_model_bytes; the engine only uses the bytes.
  std::string initial_model;
  /// The model file's bytes (engine/learning/learner_model_file.hpp; any learner kind). Not a key.
  std::string initial_model_bytes;
};

/// LearningConfig's own keys (mode, batch schedule); the LWPR block is lwpr_params_keys().
const std::vector<ConfigKey<LearningConfig>>& learning_config_keys();

/// lwpr::Kernel's spellings ("gaussian", "bisquare").
const EnumNames& lwpr_kernel_names();

/// lwpr::LooStart's spellings ("library", "early").
const EnumNames& lwpr_loo_start_names();

/// LWPR's parameter block with the published library's key names, units "" (the parameters
/// act on normalised inputs and outputs) and the ranges validate() checks; shapes of init_D,
/// norm_in and norm_out are checked by lwpr::validate_lwpr_params.
const std::vector<ConfigKey<lwpr::LwprParams>>& lwpr_params_keys();

}  // namespace armfarm
