#include "engine/experiment/job_workload.hpp"

#include "base/number_format.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// The key whose value sets the trajectory's length, blamed when a job would be too long.
const char* length_key(TrajectoryKind kind) {
  switch (kind) {
    case TrajectoryKind::sine: return "trajectory.sine.duration";
    case TrajectoryKind::figure_eight: return "trajectory.figure_eight.loops";
    case TrajectoryKind::reaching: return "trajectory.reaching.reaches";
    case TrajectoryKind::recorded: return "trajectory.recorded.loops";
  }
  return "trajectory";
}

/// The batch learner's training samples: train_fraction of the collected passes' ticks.
double calc_training_samples(const LearningConfig& learning, double ticks_per_pass) {
  return std::round(learning.train_fraction * learning.collect_repeats * ticks_per_pass);
}

/// Too many control ticks: what they are made of, and which key to change.
ConfigProblem make_ticks_problem(const JobConfig& config, const JobWorkload& work, const JobCostLimits& limits) {
  const bool heldout_to_blame = work.training_ticks <= limits.max_control_ticks;
  const double wall_minutes = work.control_ticks / 4500.0 / 60.0;  // 45 simulated s per wall s at dt = 0.01 s
  return {heldout_to_blame ? "learning.heldout_checkpoints" : length_key(config.trajectory.kind),
          "the job would take " + format_number(work.control_ticks) + " control ticks (" + format_number(work.ticks_per_pass) +
              " per pass × " + format_number(work.passes) + (work.passes == 1.0 ? " pass" : " passes") +
              (work.heldout_passes > 0.0 ? " + held-out " + format_number(work.heldout_ticks_per_pass) + " per pass × " +
                                               format_number(work.heldout_passes) + " passes (collection + one per checkpoint)"
                                         : std::string()) +
              " at dt = " + format_number(config.simulation.dt) + " s, about " + format_number(std::round(wall_minutes)) +
              " min of wall time); a job may take at most " + format_number(limits.max_control_ticks) + " ticks: " +
              (heldout_to_blame ? "fewer held-out checkpoints, a shorter learning.heldout_segments, or split it into jobs"
                                : "shorten the trajectory or split it into jobs"),
          "", std::nullopt};
}

/// SSGPR's work, updates × (2·features)² + fit_samples³ × fit_iterations, when over its bound.
std::vector<ConfigProblem> find_ssgpr_work_problems(const LearningConfig& learning, const JobWorkload& work,
                                                    const JobCostLimits& limits) {
  const double features = 2.0 * learning.ssgpr.params.features;
  const double fit = static_cast<double>(learning.ssgpr.fit_samples);
  const double cost = work.learner_updates * features * features + (fit > 0.0 ? fit * fit * fit * learning.ssgpr.fit.iterations : 0.0);
  if (cost <= limits.max_ssgpr_work) return {};
  return {{"learning.ssgpr.features",
           "the SSGPR learner would cost " + format_number(cost) + " units (" + format_number(work.learner_updates) + " updates × (2 × " +
               format_number(learning.ssgpr.params.features) + " features)² + fit_samples³ × fit_iterations); a job may cost at most " +
               format_number(limits.max_ssgpr_work) + ": fewer features, a shorter job or a smaller fit",
           "", std::nullopt}};
}

/// Too many learner updates: how they are counted, and which key to change.
ConfigProblem make_updates_problem(const JobConfig& config, const JobWorkload& work, const JobCostLimits& limits) {
  const LearningConfig& learning = config.learning;
  const bool batch = learning.mode == LearningMode::batch;
  return {batch ? "learning.epochs" : length_key(config.trajectory.kind),
          "the learner would be updated " + format_number(work.learner_updates) + " times (" +
              (batch ? format_number(learning.epochs) + " epochs × " + format_number(calc_training_samples(learning, work.ticks_per_pass)) +
                           " training samples"
                     : std::string("one per tick")) +
              "); a job may make at most " + format_number(limits.max_learner_updates) + " updates",
          "", std::nullopt};
}

}  // namespace

JobWorkload calc_job_workload(const JobConfig& config, int n) {
  const LearningConfig& learning = config.learning;
  const bool batch = learning.mode == LearningMode::batch;
  JobWorkload work;
  work.ticks_per_pass = calc_ticks_per_pass(config);
  work.passes = 1.0 + (batch ? learning.collect_repeats : 0);
  // Held-out evaluation: one collection pass, then one control pass per checkpoint.
  work.heldout_ticks_per_pass = calc_heldout_ticks_per_pass(config, n);
  work.heldout_passes =
      work.heldout_ticks_per_pass > 0.0 ? 1.0 + static_cast<double>(std::max<std::size_t>(1, learning.heldout_checkpoints.size())) : 0.0;
  work.training_ticks = work.passes * work.ticks_per_pass;
  work.control_ticks = work.training_ticks + work.heldout_passes * work.heldout_ticks_per_pass;
  if (learning.mode == LearningMode::online) work.learner_updates = work.ticks_per_pass;
  if (batch) {
    work.learner_updates = learning.epochs * calc_training_samples(learning, work.ticks_per_pass) +
                           (learning.learn_during_evaluation ? work.ticks_per_pass : 0.0);
  }
  return work;
}

std::vector<ConfigProblem> find_cost_problems(const JobConfig& config, int n, const JobCostLimits& limits) {
  const JobWorkload work = calc_job_workload(config, n);
  const LearningConfig& learning = config.learning;
  const bool ticks_fit = work.control_ticks <= limits.max_control_ticks;
  const bool updates_fit = work.learner_updates <= limits.max_learner_updates;
  std::vector<ConfigProblem> problems;
  if (!ticks_fit) problems.push_back(make_ticks_problem(config, work, limits));
  if (learning.learner == LearnerKind::ssgpr && learning.mode != LearningMode::none && ticks_fit && updates_fit) {
    for (ConfigProblem& problem : find_ssgpr_work_problems(learning, work, limits)) problems.push_back(std::move(problem));
  }
  if (ticks_fit && !updates_fit) problems.push_back(make_updates_problem(config, work, limits));
  return problems;
}

double calc_heldout_ticks_per_pass(const JobConfig& config, int n) {
  const LearningConfig& learning = config.learning;
  if (learning.mode == LearningMode::none || !learning.heldout) return 0.0;
  // The same lengths as make_heldout_config (heldout_evaluation.cpp) picks.
  JobConfig heldout = config;
  TrajectoryConfig& t = heldout.trajectory;
  const int segments = learning.heldout_segments;
  switch (t.kind) {
    case TrajectoryKind::sine: {
      double slowest = 0.0;
      try {
        const SineTrajectoryConfig sine = resolve_sine_defaults(t.sine, n, Eigen::VectorXd::Zero(n));
        for (int j = 0; j < n; ++j) {
          if (sine.amplitude[j] != 0.0 && sine.frequency[j] > 0.0 && (slowest == 0.0 || sine.frequency[j] < slowest)) {
            slowest = sine.frequency[j];
          }
        }
      } catch (const std::invalid_argument&) {
        // Mis-sized amplitude or frequency lists are reported by their keys; keep the duration.
      }
      if (slowest > 0.0) t.sine.duration = (segments > 0 ? segments : 1) / slowest;
      return calc_ticks_per_pass(heldout);
    }
    case TrajectoryKind::figure_eight: t.figure_eight.loops = segments > 0 ? segments : 1; return calc_ticks_per_pass(heldout);
    case TrajectoryKind::reaching: t.reaching.reaches = segments > 0 ? segments : 9; return calc_ticks_per_pass(heldout);
    case TrajectoryKind::recorded: {
      // The last heldout_recorded_fraction of one pass over the recording.
      t.recorded.loops = 1;
      const double rows = calc_ticks_per_pass(heldout);
      return rows - std::round((1.0 - learning.heldout_recorded_fraction) * rows);
    }
  }
  return 0.0;
}

double calc_ticks_per_pass(const JobConfig& config) {
  const TrajectoryConfig& t = config.trajectory;
  const double dt = config.simulation.dt;
  switch (t.kind) {
    case TrajectoryKind::sine: return std::max(2.0, std::round(t.sine.duration / dt));
    case TrajectoryKind::figure_eight: return static_cast<double>(t.figure_eight.points_per_loop) * t.figure_eight.loops;
    case TrajectoryKind::reaching: return static_cast<double>(t.reaching.points_per_reach) * t.reaching.reaches;
    case TrajectoryKind::recorded: return static_cast<double>(calc_recorded_ticks(t.recorded, dt)) * t.recorded.loops;
  }
  return 0.0;
}

}  // namespace armfarm
