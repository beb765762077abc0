#include "engine/experiment/heldout_evaluation.hpp"

#include "engine/experiment/collection_pass.hpp"
#include "engine/experiment/job_report.hpp"
#include "engine/experiment/signal_statistics.hpp"
#include "engine/experiment/tick_recording.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace armfarm {
namespace {

/// Rows [begin, begin + count) of `source`, replayed `loops` times (one segment per replay).
JointTrajectory slice_rows(const JointTrajectory& source, int begin, int count, int loops) {
  JointTrajectory result;
  result.dt = source.dt;
  result.q = source.q.middleRows(begin, count).replicate(loops, 1);
  result.qd = source.qd.middleRows(begin, count).replicate(loops, 1);
  result.qdd = source.qdd.middleRows(begin, count).replicate(loops, 1);
  result.task_position = source.task_position.middleRows(begin, count).replicate(loops, 1);
  for (int loop = 0; loop < loops; ++loop) result.segment_starts.push_back(loop * count);
  return result;
}

TrajectoryConfig make_heldout_config(const JobConfig& config, ArmDynamics& dynamics) {
  const LearningConfig& learning = config.learning;
  TrajectoryConfig heldout = config.trajectory;
  switch (config.trajectory.kind) {
    case TrajectoryKind::sine: {
      const int n = dynamics.dof();
      const JointRanges ranges{dynamics.lower_limits(), dynamics.upper_limits(), dynamics.velocity_limits()};
      SineTrajectoryConfig sine = resolve_sine_defaults(config.trajectory.sine, n, dynamics.start_positions(), &ranges);
      double slowest = 0.0;
      for (int j = 0; j < n; ++j) {
        if (sine.amplitude[j] != 0.0 && sine.frequency[j] > 0.0 && (slowest == 0.0 || sine.frequency[j] < slowest)) {
          slowest = sine.frequency[j];
        }
      }
      const int periods = learning.heldout_segments > 0 ? learning.heldout_segments : 1;
      if (slowest > 0.0) sine.duration = periods / slowest;
      sine.amplitude *= learning.heldout_amplitude_scale;
      for (int j = 0; j < n; ++j) sine.phase[j] += j * learning.heldout_phase_step;
      heldout.sine = sine;
      break;
    }
    case TrajectoryKind::figure_eight:
      heldout.figure_eight.scale *= learning.heldout_amplitude_scale;
      heldout.figure_eight.loops = learning.heldout_segments > 0 ? learning.heldout_segments : 1;
      break;
    case TrajectoryKind::reaching:
      heldout.reaching.reaches = learning.heldout_segments > 0 ? learning.heldout_segments : 9;
      break;
    case TrajectoryKind::recorded:
      break;
  }
  return heldout;
}

/// `recorded`'s series renamed for `checkpoint`, their time measured from the pass's first
/// recorded tick (`dt` s per tick), appended to `kept`.
void keep_heldout_series(std::vector<Series> recorded, int checkpoint, double dt, std::vector<Series>& kept) {
  for (Series& series : recorded) {
    if (series.rows.rows() > 0 && series.rows.cols() > 0) {
      const double start = series.rows(0, 0);
      for (Eigen::Index r = 0; r < series.rows.rows(); ++r) series.rows(r, 0) = calc_recorded_tick_time(series.rows(r, 0) - start, dt);
    }
    series.name = make_heldout_series_name(series.name, checkpoint);
    kept.push_back(std::move(series));
  }
}

}  // namespace

JobTrajectories build_job_trajectories(const JobConfig& config, ArmDynamics& dynamics) {
  const bool wants_heldout = config.learning.mode != LearningMode::none && config.learning.heldout;
  JobTrajectories result;
  if (!wants_heldout) {
    result.training = build_trajectory(config.trajectory, dynamics, config.simulation.dt, config.seed);
    return result;
  }
  if (config.trajectory.kind == TrajectoryKind::recorded) {
    TrajectoryConfig once = config.trajectory;
    once.recorded.loops = 1;
    const JointTrajectory whole = build_trajectory(once, dynamics, config.simulation.dt, config.seed);
    const int rows = whole.size();
    const int kept = static_cast<int>(std::lround((1.0 - config.learning.heldout_recorded_fraction) * rows));
    if (kept < 2 || rows - kept < 2) {
      throw std::invalid_argument("learning.heldout_recorded_fraction: leaves fewer than 2 samples of the " + std::to_string(rows) +
                                  "-sample recording on one side");
    }
    result.training = slice_rows(whole, 0, kept, config.trajectory.recorded.loops);
    result.heldout = slice_rows(whole, kept, rows - kept, 1);
    return result;
  }
  result.training = build_trajectory(config.trajectory, dynamics, config.simulation.dt, config.seed);
  // The reaching targets of the held-out set come from a stream of their own.
  const std::uint64_t heldout_seed = RandomStream(config.seed, "heldout.reaching").next_u64();
  result.heldout = build_trajectory(make_heldout_config(config, dynamics), dynamics, config.simulation.dt, heldout_seed);
  return result;
}

bool is_trajectory_input(const std::string& path) {
  // Everything build_job_trajectories reads: the trajectory block, the control period, the
  // seed (reaching targets), the joints (and so the kinematic chain), the start posture (the
  // sine's default offset, the IK's start and rest posture, the locked joints), the learning mode and the
  // held-out variant's keys. armature_scale changes the nominal model handed to the builders;
  // the builders use only its kinematics and limits today, but it stays in the key so that a
  // builder that one day reads the dynamics cannot be handed another arm's trajectory.
  static const char* const exact[] = {"dt", "seed", "active_joints", "start_posture", "armature_scale", "learning.mode", "learning.heldout",
                                      "learning.heldout_amplitude_scale", "learning.heldout_phase_step",
                                      "learning.heldout_segments", "learning.heldout_recorded_fraction"};
  if (path.rfind("trajectory.", 0) == 0) return true;
  // The end effector is the point task-space trajectories (figure-eight, reaching) are solved for.
  if (path.rfind("end_effector.", 0) == 0) return true;
  for (const char* key : exact) {
    if (path == key) return true;
  }
  return false;
}

HeldoutEvaluation::HeldoutEvaluation(JobSetup& setup, JointTrajectory trajectory, std::function<bool()> should_stop)
    : setup_(setup), trajectory_(std::move(trajectory)), should_stop_(std::move(should_stop)), plant_(setup.make_plant()) {}

PassResult HeldoutEvaluation::collect_test_samples() {
  samples_.clear();
  const PassResult result = collect_samples(setup_, plant_, CollectionPlan{&trajectory_, 1, "heldout"}, samples_, should_stop_);
  simulated_seconds_ += result.simulated_seconds;
  return result;
}

PassResult HeldoutEvaluation::evaluate(const Learner& learner, int checkpoint, std::vector<Metric>& metrics) {
  namespace names = metric_names;
  const ErrorFloors floors = setup_.make_error_floors();
  MetricWriter plain(metrics, setup_.joint_numbers(), {}, checkpoint);
  MetricWriter prefixed(metrics, setup_.joint_numbers(), names::heldout_prefix, checkpoint);
  plain.add(names::heldout_learner_updates, static_cast<double>(learner.n_updates()));
  plain.add(names::heldout_n_receptive_fields, static_cast<double>(learner.size()));
  plain.add(names::heldout_n_receptive_fields_per_output, calc_fields_per_output(learner));

  // (1) Prediction on the held-out samples.
  if (!samples_.empty()) {
    const int n_out = learner.output_dim();
    NmseAccumulator accuracy(n_out);
    const std::unique_ptr<PredictionWorkspace> workspace = learner.make_workspace();
    Prediction prediction;  // kept across samples: values only (the score reads no bounds)
    for (const Sample& sample : samples_) {
      learner.predict_values_into(sample.x, *workspace, prediction);
      accuracy.add(sample.y, calc_trusted_part(prediction));
    }
    plain.add_error_metrics(names::heldout_test_nmse, names::heldout_test_rmse, accuracy, floors.torque, "N·m");
    plain.add(names::heldout_n_test_samples, static_cast<double>(samples_.size()));
  }

  // (2) The job's controller with the frozen learner's feed-forward on the held-out trajectory.
  const JobConfig& config = setup_.config();
  const CompositeController controller = setup_.make_controller();
  FeedForwardProvider feed_forward(config.control, setup_.nominal(), &learner, nullptr);
  PassStatistics statistics(setup_.dof(), plant_.time(), config.statistics);
  PassOptions options;
  options.controller = &controller;
  options.feed_forward = &feed_forward;
  options.observed = &learner;
  options.statistics = &statistics;
  options.schedule_mismatch = true;
  options.should_stop = should_stop_;
  const std::vector<std::string> recorded = select_heldout_series(config.recording.series);
  SeriesRecorder recorder(recorded, setup_.joint_numbers());
  if (!recorded.empty()) {
    options.recorder = &recorder;
    options.record_every = config.recording.every;
  }
  const PassResult pass = run_control_pass(setup_, plant_, trajectory_, options);
  simulated_seconds_ += pass.simulated_seconds;
  if (!recorded.empty()) keep_heldout_series(recorder.take_series(), checkpoint, config.simulation.dt, series_);
  if (pass.status == JobStatus::timeout) return pass;
  plain.add(names::heldout_diverged, pass.status == JobStatus::diverged ? 1.0 : 0.0);
  if (statistics.ticks() > 0) statistics.write_metrics(prefixed, floors);
  return PassResult{JobStatus::done, pass.end_time, {}, pass.simulated_seconds};
}

}  // namespace armfarm
