#pragma once
// One experiment job of the thesis's simulator (chapters 5–6, appendix A): follow a desired
// trajectory with the composite controller while a learner (LWPR) learns the inverse dynamics
// online, or collect samples under feedback, train in batch and then control with the learned
// model; measure tracking, feed-forward share and model accuracy.
//
// Phases (run_experiment.cpp lists them, one file each): [learning jobs] collect the held-out
// set; [batch] collect `collect_repeats` passes of the trajectory under feedback at
// `collect_gain_scale` (each repeat a different realisation), split at random, train `epochs`
// epochs, score same_run_test_nmse; then one evaluation pass with the configured controller
// over the training trajectory (online: learning every tick). At the checkpoints the frozen
// learner is scored on the held-out set (heldout_* metrics, heldout_evaluation.hpp). [frozen]
// the learner loaded from learning.initial_model controls and is never updated (one held-out
// checkpoint, 0). Every pass starts at the trajectory's first sample at its first velocity. With
// learning.initial_model the learner starts from that model file (any learner kind); with
// learning.store_model the outcome carries the learner's model file as it is at the end.
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/job_outcome.hpp"
#include "engine/model/arm_model.hpp"

#include <functional>

namespace armfarm {

/// Runs one job. Never throws for the job's own failures: a NaN/Inf state, a tracking error
/// above the bound for too long, a velocity above the limit or an integrator failure end the job
/// with status diverged, the time and the reason; `should_stop` returning true (polled every
/// tick, and before every update and scoring prediction of batch training) ends it with status
/// timeout. Throws std::invalid_argument naming the configuration field
/// for an unusable configuration. Deterministic: the same model, config and seed give the same
/// metrics (timing metrics learner_us_* and sim_seconds_per_wall_second excepted).
/// A plain JobConfig is validated once here (validate() against make_model_facts(model)); a
/// ValidJobConfig, the proof of the runner's validation, is not validated again. Either way the
/// model must be make_job_model's for the configuration.
JobOutcome run_experiment(const ArmModel& model, const JobConfig& config, const std::function<bool()>& should_stop = {});
JobOutcome run_experiment(const ArmModel& model, const ValidJobConfig& config, const std::function<bool()>& should_stop = {});

/// The job's trajectories (training and, when it has one, the held-out variant) exactly as
/// run_experiment builds them: a pure function of the model and the configuration's keys for
/// which is_trajectory_input() holds (heldout_evaluation.hpp). Throws std::invalid_argument as
/// run_experiment does for an unusable configuration.
JobTrajectories build_job_trajectories(const ArmModel& model, const JobConfig& config);
JobTrajectories build_job_trajectories(const ArmModel& model, const ValidJobConfig& config);

/// run_experiment on trajectories built beforehand by build_job_trajectories(model, other) for a
/// configuration `other` equal to `config` on every trajectory input: the same outcome, bit for
/// bit, as building them in the job. `trajectories` is only read, so jobs may share one build.
JobOutcome run_experiment(const ArmModel& model, const JobConfig& config, const JobTrajectories& trajectories,
                          const std::function<bool()>& should_stop = {});
JobOutcome run_experiment(const ArmModel& model, const ValidJobConfig& config, const JobTrajectories& trajectories,
                          const std::function<bool()>& should_stop = {});

}  // namespace armfarm
