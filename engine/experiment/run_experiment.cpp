// One experiment job as a list of phases (each in its own file under engine/experiment/):
//   validation       job_config_validation  the one validate() (done at the edge: a ValidJobConfig)
//   setup            job_setup          joints, nominal model, gains, the true plant, the PD and
//                                       integrator steps (job_steps: "auto" by the criterion)
//   trajectories     heldout_evaluation the training trajectory and its held-out variant
//   learner          learner_factory    one factory from the learning config (Learner interface),
//                    learner_model_file or the model file the job starts from (learning.initial_model)
//   held-out set     heldout_evaluation test samples collected once, never learnt
//   collection       collection_pass    batch: repeats under feedback, each a different realisation
//   training         batch_training     batch: epochs over a random split (same_run_test_nmse)
//   evaluation       control_pass       the configured controller over the training trajectory
//                                       (online: learning every tick), with the feed-forward
//                                       source (feed_forward_source) and the divergence monitor
//                                       (divergence_monitor) inside every pass
//   checkpoints      heldout_evaluation the frozen learner on the held-out set (heldout_*)
//   recording        job_report         metrics, TRIAL rows, cost; the learner's model file
//                    learner_model_file (learning.store_model)
#include "engine/experiment/run_experiment.hpp"

#include "engine/experiment/batch_training.hpp"
#include "engine/experiment/collection_pass.hpp"
#include "engine/experiment/control_pass.hpp"
#include "engine/experiment/experiment_metrics.hpp"
#include "engine/experiment/feed_forward_source.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/job_model.hpp"
#include "engine/experiment/job_report.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/pass_statistics.hpp"
#include "engine/experiment/series_recorder.hpp"
#include "engine/learning/learner_factory.hpp"
#include "engine/learning/learner_model_file.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <variant>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {
namespace {

using Clock = std::chrono::steady_clock;

/// The checkpoints of the held-out evaluation, in the mode's unit of learning progress
/// (online: completed segments of the learning pass; batch: epochs), `last` when none are given.
std::vector<int> resolve_checkpoints(const LearningConfig& learning, int last, const std::string& unit) {
  if (learning.heldout_checkpoints.empty()) return {last};
  for (std::size_t i = 0; i < learning.heldout_checkpoints.size(); ++i) {
    if (learning.heldout_checkpoints[i] > last) {
      throw std::invalid_argument("learning.heldout_checkpoints[" + std::to_string(i) + "]: " +
                                  std::to_string(learning.heldout_checkpoints[i]) + " is beyond the job's " +
                                  std::to_string(last) + " " + unit);
    }
  }
  return learning.heldout_checkpoints;
}

// The engine's own precondition: `model` is the job's (make_job_model of its file for `config`).
void require_job_model(const ArmModel& model, const JobConfig& config) {
  if (const std::string problem = check_job_model(model, config); !problem.empty()) {
    throw std::invalid_argument(model.source_file + ": " + problem);
  }
}

// The one check of a plain JobConfig at the engine's entry (a ValidJobConfig has had it).
ValidJobConfig check_config(const ArmModel& model, const JobConfig& config) {
  std::variant<ValidJobConfig, std::vector<ConfigProblem>> checked = check_job_config(config, make_model_facts(model));
  if (auto* problems = std::get_if<std::vector<ConfigProblem>>(&checked)) throw std::invalid_argument(make_problems_text(*problems));
  return std::get<ValidJobConfig>(std::move(checked));
}

/// The job itself, on its trajectories (`built` when the job built them, else `shared`).
JobOutcome run_job(const ArmModel& model, const JobConfig& config, const JobTrajectories* shared, const std::function<bool()>& should_stop) {
  const Clock::time_point wall_start = Clock::now();
  JobOutcome outcome;
  double simulated_seconds = 0.0;
  LearnerClock learner_clock;

  // Setup (the configuration was checked once, at the edge: a ValidJobConfig), trajectories, learner.
  require_job_model(model, config);
  JobSetup setup(model, config);
  MetricWriter metrics(outcome.metrics, setup.joint_numbers());
  JobTrajectories built;
  if (!shared) built = build_job_trajectories(config, setup.nominal());
  const JobTrajectories& trajectories = shared ? *shared : built;
  const JointTrajectory& training = trajectories.training;
  if (training.size() < 2) throw std::invalid_argument("trajectory: needs at least 2 samples");
  // "auto" steps: the criterion over the postures the job's passes visit.
  setup.fit_to_trajectories({&training, trajectories.heldout ? &*trajectories.heldout : nullptr});
  // Steps the criterion calls unstable there (validate() judged the start posture alone) are refused.
  if (!setup.step_problems().empty()) {
    const StepProblem& problem = setup.step_problems().front();
    throw std::invalid_argument(problem.key + ": " + problem.message);
  }
  const int n = setup.dof();
  std::unique_ptr<Learner> learner;
  if (config.learning.mode != LearningMode::none && !config.learning.initial_model_bytes.empty()) {
    learner = decode_learner_model(config.learning.initial_model_bytes);  // checked by validate()
  } else if (config.learning.mode != LearningMode::none) {
    learner = make_learner(config.learning, 3 * n, n,
                           config.learning.normalize_inputs ? calc_trajectory_input_scale(training) : Eigen::VectorXd());
  }
  std::vector<int> checkpoints;
  if (config.learning.mode == LearningMode::batch) {
    checkpoints = resolve_checkpoints(config.learning, config.learning.epochs, "epochs");
  } else if (config.learning.mode == LearningMode::online) {
    checkpoints = resolve_checkpoints(config.learning, static_cast<int>(training.segment_starts.size()), "segments");
  } else if (config.learning.mode == LearningMode::frozen) {
    checkpoints = {0};  // the learner never changes: one evaluation
  }
  SeriesRecorder recorder(select_pass_series(config.recording.series), setup.joint_numbers());
  ArmSimulation plant = setup.make_plant();

  std::optional<HeldoutEvaluation> heldout;
  const auto finish = [&](const PassResult& result) {
    outcome.status = result.status;
    outcome.message = result.message;
    outcome.end_time = result.end_time;
    const double total = simulated_seconds + (heldout ? heldout->simulated_seconds() : 0.0);
    write_cost_report(metrics, total, std::chrono::duration<double>(Clock::now() - wall_start).count());
    metrics.add(metric_names::pd_substeps_used, setup.pd_substeps());
    metrics.add(metric_names::integrator_steps_used, setup.integrator_steps());
    outcome.series = recorder.take_series();
    if (heldout) {
      for (Series& series : heldout->take_series()) outcome.series.push_back(std::move(series));
    }
    if (learner && config.learning.store_model) outcome.model_file = encode_learner_model(*learner);
    return std::move(outcome);
  };

  // Held-out set: its test samples, collected before anything is learnt.
  const auto evaluate_heldout_at = [&](int progress) -> PassResult {
    if (!heldout || std::find(checkpoints.begin(), checkpoints.end(), progress) == checkpoints.end()) return {};
    return heldout->evaluate(*learner, progress, outcome.metrics);
  };
  if (trajectories.heldout) {
    heldout.emplace(setup, shared ? *trajectories.heldout : std::move(*built.heldout), should_stop);
    PassResult collected = heldout->collect_test_samples();
    if (!collected.ok()) return finish({collected.status, collected.end_time, "held-out collection: " + collected.message});
  }

  // Batch: collection, then training (held-out checkpoints after chosen epochs).
  BatchTrainingResult batch;
  if (config.learning.mode == LearningMode::batch) {
    std::vector<Sample> samples;
    const PassResult collected =
        collect_samples(setup, plant, CollectionPlan{&training, config.learning.collect_repeats, "collection"}, samples, should_stop);
    simulated_seconds += collected.simulated_seconds;
    if (!collected.ok()) return finish(collected);
    PassResult trained =
        train_in_batch(*learner, samples, config.learning, config.seed, &learner_clock, evaluate_heldout_at, should_stop, batch);
    if (batch.stopped) trained.end_time = collected.end_time;  // training itself advances no plant time
    if (!trained.ok()) return finish(trained);
  }

  // Evaluation pass over the training trajectory (online: the learning pass, held-out
  // checkpoints after chosen segments).
  const CompositeController controller = setup.make_controller();
  FeedForwardProvider feed_forward(config.control, setup.nominal(), learner.get(), &learner_clock);
  PassStatistics statistics(n, plant.time(), config.statistics);
  PassOptions options;
  options.controller = &controller;
  options.feed_forward = &feed_forward;
  options.observed = learner.get();
  options.clock = &learner_clock;
  TickClock tick_clock;
  options.tick_clock = &tick_clock;
  options.statistics = &statistics;
  options.recorder = &recorder;
  options.record_every = config.recording.every;
  options.schedule_mismatch = true;
  options.should_stop = should_stop;
  const bool learns = config.learning.mode == LearningMode::online ||
                      (config.learning.mode == LearningMode::batch && config.learning.learn_during_evaluation);
  if (learns) options.learner = learner.get();
  if (config.learning.mode == LearningMode::frozen) {
    const PassResult frozen = evaluate_heldout_at(0);
    if (!frozen.ok()) return finish(frozen);
  }
  if (config.learning.mode == LearningMode::online) {
    options.on_segment_end = evaluate_heldout_at;
    const PassResult before = evaluate_heldout_at(0);
    if (!before.ok()) return finish(before);
  }
  const PassResult evaluated = run_control_pass(setup, plant, training, options);
  simulated_seconds += evaluated.simulated_seconds;
  if (!evaluated.ok()) return finish(evaluated);

  // Recording.
  const ErrorFloors floors = setup.make_error_floors();
  write_evaluation_report(metrics, statistics, floors, recorder);
  if (config.learning.mode == LearningMode::batch) write_batch_training_report(metrics, batch, floors);
  if (learner) write_learner_report(metrics, *learner, learner_clock);
  write_tick_report(metrics, tick_clock);
  return finish(evaluated);
}

}  // namespace

JobOutcome run_experiment(const ArmModel& model, const ValidJobConfig& config, const std::function<bool()>& should_stop) {
  return run_job(model, config, nullptr, should_stop);
}

JobOutcome run_experiment(const ArmModel& model, const ValidJobConfig& config, const JobTrajectories& trajectories,
                          const std::function<bool()>& should_stop) {
  return run_job(model, config, &trajectories, should_stop);
}

JobOutcome run_experiment(const ArmModel& model, const JobConfig& config, const std::function<bool()>& should_stop) {
  return run_experiment(model, check_config(model, config), should_stop);
}

JobOutcome run_experiment(const ArmModel& model, const JobConfig& config, const JobTrajectories& trajectories,
                          const std::function<bool()>& should_stop) {
  return run_experiment(model, check_config(model, config), trajectories, should_stop);
}

JobTrajectories build_job_trajectories(const ArmModel& model, const ValidJobConfig& config) {
  require_job_model(model, config);
  JobSetup setup(model, config);
  return build_job_trajectories(config.get(), setup.nominal());
}

JobTrajectories build_job_trajectories(const ArmModel& model, const JobConfig& config) {
  return build_job_trajectories(model, check_config(model, config));
}

}  // namespace armfarm
