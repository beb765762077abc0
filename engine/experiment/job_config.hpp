#pragma once
// Everything one experiment job needs, as a plain immutable description with the documented
// defaults (sweeps/README.md lists every field with its unit and JSON key). The runner parses
// it from JSON; the engine never reads JSON.
//
// Units: SI and radians. Per-joint vectors have one entry per active joint, in the order of
// `active_joints`; a 1-element vector applies to every active joint; an empty vector means
// "the default rule" stated at the field.
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace armfarm {

/// The thesis's three control modes (appendix A).
enum class ControlMode {
  open_loop,  ///< feed-forward only
  feedback,   ///< PD only
  composite,  ///< PD + feed-forward
};

/// Where the feed-forward torque comes from.
enum class FeedForwardSource {
  learner,   ///< the learned inverse dynamics (LWPR) at the desired state
  analytic,  ///< the exact rigid-body inverse dynamics of the nominal model (section 3.1)
  none,
};

struct ControlConfig {
  ControlMode mode = ControlMode::composite;
  FeedForwardSource feed_forward = FeedForwardSource::learner;
  /// PD gains, N·m/rad and N·m·s/rad. Empty: kp = M_jj·bandwidth², kd = 2·damping_ratio·M_jj·bandwidth
  /// with M_jj the diagonal of the mass matrix (armature included) at the start posture.
  Eigen::VectorXd kp;
  Eigen::VectorXd kd;
  double bandwidth = 20.0;     ///< rad/s, for the default gains (stable under a 10 ms hold)
  double damping_ratio = 1.0;  ///< for the default gains
  /// Multiplies both gains; the thesis's low-gain controller is 0.2 (gains reduced by 80 %).
  double gain_scale = 1.0;
  bool limit_torque = true;    ///< clip the command to the model's effort limits
};

/// The learners the factory knows (a second one, e.g. SSGPR, is added here and in the factory).
enum class LearnerKind {
  lwpr,  ///< locally weighted projection regression (engine/lwpr/)
};

enum class LearningMode {
  none,    ///< no learner (feedback, or analytic feed-forward)
  online,  ///< learn every tick while controlling with the learner's prediction
  batch,   ///< collect under feedback, train offline, then control with the frozen model
};

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
  /// Which learner the factory (engine/learning/learner_factory.hpp) builds.
  LearnerKind learner = LearnerKind::lwpr;

  /// Batch: every collection repeat after the first starts off the trajectory by a seeded
  /// normal draw of this standard deviation per joint angle (rad; stream "collection.start_state"),
  /// so a repeat is a different realisation of the run, never a copy. 0 = exact copies.
  double collect_start_spread = 0.05;
  /// Batch: standard deviation of the sensor noise added to the measured q (rad) and q̇ (rad/s)
  /// that the collecting controller and the recorded samples see (stream "collection.sensor_noise").
  double collect_noise_q = 0.0;
  double collect_noise_qd = 0.0;

  /// Held-out evaluation (online and batch): the learner, frozen, is scored on a different
  /// realisation of the trajectory it never trained on (heldout_* metrics). See heldout_evaluation.hpp.
  bool heldout = true;
  /// When to evaluate: online, after this many completed segments of the learning pass (reaches
  /// for reaching, periods of the slowest joint for sine, loops for figure-eight and recorded;
  /// 0 = before learning); batch, after this many training epochs. Empty: once, at the end.
  std::vector<int> heldout_checkpoints;
  /// Segments of the held-out trajectory (reaches, periods, loops); 0: 9 reaches (the thesis's
  /// 9 held-out transitions), otherwise 1 period or loop. Ignored for recorded motion.
  int heldout_segments = 0;
  /// Sine and figure-eight: the held-out variant's amplitude (figure-eight: scale) relative to the
  /// training trajectory's.
  double heldout_amplitude_scale = 0.8;
  /// Sine: the held-out variant adds (i − 1)·this phase (rad) to the i-th active joint (relative
  /// phases change, so the joint-space path differs, not just its start time).
  double heldout_phase_step = 0.785398163397448;  // π/4
  /// Recorded motion: the last fraction of the recording is held out and never trained on (the
  /// learning pass replays the rest).
  double heldout_recorded_fraction = 0.25;
};

/// Model mismatch: the plant differs from the nominal model the analytic feed-forward uses.
struct MismatchConfig {
  Payload payload;               ///< at the end effector
  Eigen::VectorXd viscous;       ///< N·m·s/rad, replaces the model's damping (empty: the model's)
  Eigen::VectorXd coulomb;       ///< N·m, replaces the model's friction (empty: the model's)
  double start_time = 0.0;       ///< s into the evaluation run at which the mismatch appears
};

struct RecordingConfig {
  std::vector<std::string> series;  ///< POS, POS_D, PHI, PHI_D, VEL, VEL_D, ACC, ACC_D, TOR, F, FF, RF, TRIAL
  int every = 1;                    ///< keep one sample in `every` control ticks
};

/// When a job is declared diverged.
struct DivergenceConfig {
  double max_tracking_error = 1.0;     ///< rad, on any joint ...
  double max_error_duration = 0.5;     ///< s, ... for longer than this
  double velocity_limit_factor = 1.5;  ///< |q̇| above this × the model's velocity limit (a runaway, not a fast move)
};

struct JobConfig {
  std::vector<int> active_joints;  ///< 1-based movable joint numbers (the thesis's "Joint 2"); empty = all
  double dt = 0.01;                ///< s, control and learning period (the thesis's TAU)
  IntegratorKind integrator = IntegratorKind::runge_kutta_merson;
  double integrator_accuracy = 1e-5;
  ControlConfig control;
  TrajectoryConfig trajectory;
  LearningConfig learning;
  MismatchConfig mismatch;
  RecordingConfig recording;
  DivergenceConfig divergence;
  std::uint64_t seed = 0;
};

}  // namespace armfarm
