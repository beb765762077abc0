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
// In this file run_job makes the setup and the trajectories; ExperimentRun holds what the other
// phases share and runs each as a named step (held-out set, batch collection and training,
// evaluation and recording, finish). Stage timing stays out of the physics: the control pass's
// TickLaps and ScopedSeconds (tick_timer.hpp).
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
#include <functional>
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

/// The job's training trajectory checked and the "auto" steps fitted to the postures the job's
/// passes visit (training and held-out). Throws std::invalid_argument for a trajectory of fewer
/// than 2 samples, or naming the key of a step the criterion calls unstable there.
void fit_steps_to_trajectories(JobSetup& setup, const JobTrajectories& trajectories) {
  const JointTrajectory& training = trajectories.training;
  if (training.size() < 2) throw std::invalid_argument("trajectory: needs at least 2 samples");
  // "auto" steps: the criterion over the postures the job's passes visit.
  setup.fit_to_trajectories({&training, trajectories.heldout ? &*trajectories.heldout : nullptr});
  // Steps the criterion calls unstable there (validate() judged the start posture alone) are refused.
  if (!setup.step_problems().empty()) {
    const StepProblem& problem = setup.step_problems().front();
    throw std::invalid_argument(problem.key + ": " + problem.message);
  }
}

/// The job's learner of the inverse dynamics, 3n inputs (q, q̇, q̈) to n torques: none when
/// nothing learns; the model file the job starts from (learning.initial_model, checked by
/// validate()); else a new one from the learning config (input scales from `training` with
/// learning.normalize_inputs).
std::unique_ptr<Learner> make_job_learner(const LearningConfig& learning, int n, const JointTrajectory& training) {
  if (learning.mode == LearningMode::none) return nullptr;
  if (!learning.initial_model_bytes.empty()) return decode_learner_model(learning.initial_model_bytes);
  return make_learner(learning, 3 * n, n, learning.normalize_inputs ? calc_trajectory_input_scale(training) : Eigen::VectorXd());
}

/// The held-out checkpoints in the mode's unit of learning progress: batch epochs, online
/// completed segments of `training`, frozen the single checkpoint 0, none (no learner) none.
/// Throws std::invalid_argument naming learning.heldout_checkpoints[i] beyond the job's end.
std::vector<int> resolve_job_checkpoints(const LearningConfig& learning, const JointTrajectory& training) {
  switch (learning.mode) {
    case LearningMode::batch: return resolve_checkpoints(learning, learning.epochs, "epochs");
    case LearningMode::online: return resolve_checkpoints(learning, static_cast<int>(training.segment_starts.size()), "segments");
    case LearningMode::frozen: return {0};  // the learner never changes: one evaluation
    case LearningMode::none: break;
  }
  return {};
}

/// Whether the evaluation pass updates the learner: online always, batch with
/// learning.learn_during_evaluation.
bool learns_during_evaluation(const LearningConfig& learning) {
  return learning.mode == LearningMode::online || (learning.mode == LearningMode::batch && learning.learn_during_evaluation);
}

/// One job after its setup: the state its phases share (learner, plant, held-out set, clocks,
/// metrics) and each phase as a named step. A phase that ends the job early returns its
/// PassResult; finish() turns the last result into the outcome. Lives on one thread.
class ExperimentRun {
 public:
  /// `trajectories` are the job's (fitted by fit_steps_to_trajectories); `built` is the same
  /// object when the job built them (its held-out trajectory is then moved, not copied), else null.
  ExperimentRun(JobSetup& setup, const JobTrajectories& trajectories, JobTrajectories* built,
                const std::function<bool()>& should_stop, Clock::time_point wall_start)
      : setup_(setup),
        config_(setup.config()),
        trajectories_(trajectories),
        built_(built),
        training_(trajectories.training),
        should_stop_(should_stop),
        wall_start_(wall_start),
        metrics_(outcome_.metrics, setup.joint_numbers()),
        learner_(make_job_learner(config_.learning, setup.dof(), training_)),
        checkpoints_(resolve_job_checkpoints(config_.learning, training_)),
        recorder_(select_pass_series(config_.recording.series), setup.joint_numbers()),
        plant_(setup.make_plant()) {}

  /// The phases in order: held-out set, [batch] collection and training, evaluation and its
  /// recording; whichever ends the job, finish() makes the outcome.
  JobOutcome run() {
    if (std::optional<PassResult> end = collect_heldout_set()) return finish(*end);
    BatchTrainingResult batch;
    if (config_.learning.mode == LearningMode::batch) {
      if (std::optional<PassResult> end = collect_and_train(batch)) return finish(*end);
    }
    return finish(evaluate_and_record(batch));
  }

 private:
  /// Held-out set: its test samples, collected before anything is learnt (when the job has one).
  std::optional<PassResult> collect_heldout_set() {
    if (!trajectories_.heldout) return std::nullopt;
    heldout_.emplace(setup_, !built_ ? *trajectories_.heldout : std::move(*built_->heldout), should_stop_);
    PassResult collected = heldout_->collect_test_samples();
    if (!collected.ok()) return PassResult{collected.status, collected.end_time, "held-out collection: " + collected.message};
    return std::nullopt;
  }

  /// Batch: collection under feedback, then training (held-out checkpoints after chosen epochs).
  std::optional<PassResult> collect_and_train(BatchTrainingResult& batch) {
    std::vector<Sample> samples;
    const PassResult collected = collect_samples(
        setup_, plant_, CollectionPlan{&training_, config_.learning.collect_repeats, "collection"}, samples, should_stop_);
    simulated_seconds_ += collected.simulated_seconds;
    if (!collected.ok()) return collected;
    PassResult trained = train_in_batch(*learner_, samples, config_.learning, config_.seed, &learner_clock_,
                                        evaluate_heldout_callback(), should_stop_, batch);
    if (batch.stopped) trained.end_time = collected.end_time;  // training itself advances no plant time
    if (!trained.ok()) return trained;
    return std::nullopt;
  }

  /// Evaluation pass over the training trajectory with the configured controller (online: the
  /// learning pass, held-out checkpoints after chosen segments; frozen: its one checkpoint
  /// first); when the pass completes, the recording of its figures.
  PassResult evaluate_and_record(const BatchTrainingResult& batch) {
    const CompositeController controller = setup_.make_controller();
    FeedForwardProvider feed_forward(config_.control, setup_.nominal(), learner_.get(), &learner_clock_);
    PassStatistics statistics(setup_.dof(), plant_.time(), config_.statistics);
    TickClock tick_clock;
    PassOptions options = make_evaluation_options(controller, feed_forward, statistics, tick_clock);
    if (config_.learning.mode == LearningMode::frozen) {
      const PassResult frozen = evaluate_heldout_at(0);
      if (!frozen.ok()) return frozen;
    }
    if (config_.learning.mode == LearningMode::online) {
      options.on_segment_end = evaluate_heldout_callback();
      const PassResult before = evaluate_heldout_at(0);
      if (!before.ok()) return before;
    }
    const PassResult evaluated = run_control_pass(setup_, plant_, training_, options);
    simulated_seconds_ += evaluated.simulated_seconds;
    if (evaluated.ok()) write_reports(statistics, batch, tick_clock);
    return evaluated;
  }

  /// The evaluation pass's options: every stage on (statistics, recording, stage timing, the
  /// scheduled mismatch), the learner observed and, when it learns then, updated.
  PassOptions make_evaluation_options(const CompositeController& controller, FeedForwardProvider& feed_forward,
                                      PassStatistics& statistics, TickClock& tick_clock) {
    PassOptions options;
    options.controller = &controller;
    options.feed_forward = &feed_forward;
    options.observed = learner_.get();
    options.clock = &learner_clock_;
    options.tick_clock = &tick_clock;
    options.statistics = &statistics;
    options.recorder = &recorder_;
    options.record_every = config_.recording.every;
    options.schedule_mismatch = true;
    options.should_stop = should_stop_;
    if (learns_during_evaluation(config_.learning)) options.learner = learner_.get();
    return options;
  }

  /// The figures of a completed evaluation: tracking, batch training, the learner, the ticks' stages.
  void write_reports(const PassStatistics& statistics, const BatchTrainingResult& batch, const TickClock& tick_clock) {
    const ErrorFloors floors = setup_.make_error_floors();
    write_evaluation_report(metrics_, statistics, floors, recorder_);
    if (config_.learning.mode == LearningMode::batch) write_batch_training_report(metrics_, batch, floors);
    if (learner_) write_learner_report(metrics_, *learner_, learner_clock_);
    write_tick_report(metrics_, tick_clock);
  }

  /// The frozen learner on the held-out set when `progress` is one of the checkpoints (else ok).
  PassResult evaluate_heldout_at(int progress) {
    if (!heldout_ || std::find(checkpoints_.begin(), checkpoints_.end(), progress) == checkpoints_.end()) return {};
    return heldout_->evaluate(*learner_, progress, outcome_.metrics);
  }
  std::function<PassResult(int)> evaluate_heldout_callback() {
    return [this](int progress) { return evaluate_heldout_at(progress); };
  }

  /// The outcome, whichever phase ended the job: `result`'s status, the cost (simulated seconds
  /// of every pass, wall seconds since the job started), the steps used, the series and, with
  /// learning.store_model, the learner's model file. Called once.
  JobOutcome finish(const PassResult& result) {
    outcome_.status = result.status;
    outcome_.message = result.message;
    outcome_.end_time = result.end_time;
    const double total = simulated_seconds_ + (heldout_ ? heldout_->simulated_seconds() : 0.0);
    write_cost_report(metrics_, total, std::chrono::duration<double>(Clock::now() - wall_start_).count());
    metrics_.add(metric_names::pd_substeps_used, setup_.pd_substeps());
    metrics_.add(metric_names::integrator_steps_used, setup_.integrator_steps());
    outcome_.series = recorder_.take_series();
    if (heldout_) {
      for (Series& series : heldout_->take_series()) outcome_.series.push_back(std::move(series));
    }
    if (learner_ && config_.learning.store_model) outcome_.model_file = encode_learner_model(*learner_);
    return std::move(outcome_);
  }

  JobSetup& setup_;
  const JobConfig& config_;
  const JobTrajectories& trajectories_;
  JobTrajectories* built_;  // == &trajectories_ when the job built them, else null
  const JointTrajectory& training_;
  const std::function<bool()>& should_stop_;
  const Clock::time_point wall_start_;
  JobOutcome outcome_;  // declared before metrics_, which writes into it
  MetricWriter metrics_;
  double simulated_seconds_ = 0.0;  // of the job's own passes (the held-out set counts its own)
  LearnerClock learner_clock_;
  std::unique_ptr<Learner> learner_;
  std::vector<int> checkpoints_;
  SeriesRecorder recorder_;
  ArmSimulation plant_;
  std::optional<HeldoutEvaluation> heldout_;
};

/// The job itself, on its trajectories (`shared` when given, else built here): the engine's
/// precondition on the model, the setup, the trajectories and steps, then ExperimentRun's phases.
/// The configuration was checked once, at the edge (a ValidJobConfig).
JobOutcome run_job(const ArmModel& model, const JobConfig& config, const JobTrajectories* shared, const std::function<bool()>& should_stop) {
  const Clock::time_point wall_start = Clock::now();
  require_job_model(model, config);
  JobSetup setup(model, config);
  JobTrajectories built;
  if (!shared) built = build_job_trajectories(config, setup.nominal());
  const JobTrajectories& trajectories = shared ? *shared : built;
  fit_steps_to_trajectories(setup, trajectories);
  ExperimentRun run(setup, trajectories, shared ? nullptr : &built, should_stop, wall_start);
  return run.run();
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
