#include "engine/experiment/control_pass.hpp"

#include "engine/experiment/divergence_advice.hpp"
#include "engine/experiment/divergence_monitor.hpp"
#include "engine/experiment/tick_recording.hpp"
#include "engine/experiment/tick_timer.hpp"

#include <optional>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// The measured state: the plant's plus the configured sensor noise.
struct Measurement {
  Eigen::VectorXd q, qd;
};

Measurement measure(const ArmSimulation& plant, const PassOptions& options) {
  Measurement m{plant.q(), plant.qd()};
  if (options.noise && options.noise_q > 0.0) {
    for (Eigen::Index j = 0; j < m.q.size(); ++j) m.q[j] += options.noise->normal(0.0, options.noise_q);
  }
  if (options.noise && options.noise_qd > 0.0) {
    for (Eigen::Index j = 0; j < m.qd.size(); ++j) m.qd[j] += options.noise->normal(0.0, options.noise_qd);
  }
  return m;
}

struct DesiredState {
  const Eigen::VectorXd& q;
  const Eigen::VectorXd& qd;
  const Eigen::VectorXd& qdd;
};

// Steps the plant over one tick of `dt` and returns the torque averaged over it. With one
// substep the tick's command is held (the thesis's loop); with more, the PD term is recomputed
// every dt / substeps on the measured plant state against the desired state extrapolated from
// the tick's start (q + q̇·s, q̇ + q̈·s), the feed-forward held.
Eigen::VectorXd step_tick(ArmSimulation& plant, const CompositeController& controller, const ControlCommand& command,
                          const Eigen::VectorXd& feed_forward, const DesiredState& desired, double dt, int substeps,
                          const PassOptions& options) {
  if (substeps <= 1) {
    plant.step(command.torque, dt);
    return command.torque;
  }
  const double h = dt / substeps;
  Eigen::VectorXd total = command.torque;
  plant.step(command.torque, h);
  for (int s = 1; s < substeps; ++s) {
    const double elapsed = s * h;
    const Measurement m = measure(plant, options);
    const ControlCommand sub = controller.calc_command(desired.q + desired.qd * elapsed, desired.qd + desired.qdd * elapsed,
                                                      m.q, m.qd, feed_forward);
    plant.step(sub.torque, h);
    total += sub.torque;
  }
  return total / substeps;
}

PassResult end_pass(JobStatus status, double time, std::string message, double simulated) {
  return PassResult{status, time, std::move(message), simulated};
}

/// The desired and measured state of one tick: the trajectory's row k and the plant's true state.
struct TickState {
  double t;
  Eigen::VectorXd q_desired, qd_desired, qdd_desired;
  Eigen::VectorXd q, qd;  ///< the plant's (not the measured) state
};

/// One control pass over a trajectory: the state the ticks carry, and each tick as named steps.
/// Every step that ends the pass returns its PassResult.
class ControlPassRun {
 public:
  ControlPassRun(JobSetup& setup, ArmSimulation& plant, const JointTrajectory& trajectory, const PassOptions& options)
      : setup_(setup),
        plant_(plant),
        trajectory_(trajectory),
        options_(options),
        config_(setup.config()),
        divergence_(config_.divergence, setup.nominal().velocity_limits(), setup.joint_numbers()) {
    place_plant_at_start();
  }

  /// Tick k: checkpoints, command, statistics, plant step, learning; a result ends the pass.
  std::optional<PassResult> run_tick(int k) {
    TickLaps laps(options_.tick_clock);
    const double t = plant_.time();
    if (auto end = enter_tick(k, t, laps)) return end;
    const TickState tick = read_tick(k, t);
    if (auto end = check_divergence(tick)) return end;
    laps.lap(&TickClock::control);

    FeedForwardTerm feed_forward{Eigen::VectorXd::Zero(setup_.dof())};
    if (options_.feed_forward) feed_forward = options_.feed_forward->calc(tick.q_desired, tick.qd_desired, tick.qdd_desired);
    laps.lap(&TickClock::feed_forward);
    const ControlCommand command =
        options_.controller->calc_command(tick.q_desired, tick.qd_desired, measured_.q, measured_.qd, feed_forward.torque);
    laps.lap(&TickClock::control);

    if (options_.statistics) add_statistics(k, tick, command, feed_forward, laps);
    Eigen::VectorXd applied_torque;  // averaged over the tick: the learner's target
    if (auto end = step_plant(tick, command, feed_forward, applied_torque)) return end;
    laps.lap(&TickClock::physics);
    if (auto end = learn(applied_torque)) return end;
    laps.lap(&TickClock::learning);
    return std::nullopt;
  }

  /// After the last tick: the statistics' end and the last segment's checkpoint.
  PassResult finish() {
    if (options_.statistics) options_.statistics->end(observed_size());
    if (options_.on_segment_end) {
      PassResult checkpoint = options_.on_segment_end(static_cast<int>(trajectory_.segment_starts.size()));
      if (!checkpoint.ok()) return end_pass(checkpoint.status, plant_.time(), checkpoint.message, simulated_);
    }
    return end_pass(JobStatus::done, plant_.time(), {}, simulated_);
  }

 private:
  std::size_t observed_size() const { return options_.observed ? options_.observed->size() : 0; }

  /// The plant at the trajectory's first sample (plus start_offset), the mismatch as scheduled.
  void place_plant_at_start() {
    pass_start_ = plant_.time();
    mismatch_present_ = setup_.mismatch_from_start();
    if (options_.schedule_mismatch && !mismatch_present_ && setup_.has_mismatch()) setup_.remove_mismatch(plant_);
    Eigen::VectorXd q_start = trajectory_.q.row(0).transpose();
    if (options_.start_offset.size()) q_start += options_.start_offset;
    plant_.set_state(pass_start_, q_start, trajectory_.qd.row(0).transpose());
    last_acceleration_ = Eigen::VectorXd::Zero(setup_.dof());
    measured_ = measure(plant_, options_);
    last_finite_q_ = plant_.q();
    last_desired_q_ = last_finite_q_;
  }

  /// Before tick k (at plant time t): a stop request, the mismatch's scheduled start, a segment's checkpoint.
  std::optional<PassResult> enter_tick(int k, double t, TickLaps& laps) {
    if (options_.should_stop && options_.should_stop()) return end_pass(JobStatus::timeout, t, "stopped before the end of the run", simulated_);
    if (options_.schedule_mismatch && !mismatch_present_ && t - pass_start_ >= config_.mismatch.start_time - 1e-12) {
      setup_.apply_mismatch(plant_);
      mismatch_present_ = true;
    }
    const std::size_t segments = trajectory_.segment_starts.size();
    if (segment_ + 1 < segments && k == trajectory_.segment_starts[segment_ + 1]) {
      ++segment_;
      if (options_.statistics) options_.statistics->start_segment(t, observed_size());
      if (options_.on_segment_end) {
        PassResult checkpoint = options_.on_segment_end(static_cast<int>(segment_));
        if (!checkpoint.ok()) return end_pass(checkpoint.status, t, checkpoint.message, simulated_);
        laps.restart();  // a checkpoint's passes are not this tick's work
      }
    }
    return std::nullopt;
  }

  TickState read_tick(int k, double t) const {
    return TickState{t,
                     trajectory_.q.row(k).transpose(),
                     trajectory_.qd.row(k).transpose(),
                     trajectory_.qdd.row(k).transpose(),
                     plant_.q(),
                     plant_.qd()};
  }

  PassResult diverged(double t, const std::string& reason) const {
    return end_pass(JobStatus::diverged, t,
                    reason + make_divergence_advice(setup_, *options_.controller, trajectory_, last_finite_q_, last_desired_q_),
                    simulated_);
  }

  std::optional<PassResult> check_divergence(const TickState& tick) {
    if (tick.q.allFinite()) {
      last_finite_q_ = tick.q;
      last_desired_q_ = tick.q_desired;
    }
    if (auto reason = divergence_.check(tick.t, tick.q, tick.qd, tick.q_desired)) return diverged(tick.t, *reason);
    return std::nullopt;
  }

  /// Tracking statistics, the learned model's accuracy against the true dynamics, the series.
  void add_statistics(int k, const TickState& tick, const ControlCommand& command, const FeedForwardTerm& feed_forward,
                      TickLaps& laps) {
    const Eigen::Vector3d position = setup_.end_effector().calc_position(tick.q);
    const Eigen::Vector3d position_desired = trajectory_.task_position.row(k).transpose();
    options_.statistics->add_tick(tick.q_desired, tick.q, position_desired, position, command);
    if (feed_forward.from_learner) {
      laps.lap(&TickClock::statistics);
      const Eigen::VectorXd true_torque = setup_.calc_true_torque(tick.q_desired, tick.qd_desired, tick.qdd_desired, mismatch_present_);
      laps.lap(&TickClock::true_dynamics);
      options_.statistics->add_model_accuracy(true_torque, feed_forward.torque, feed_forward.output_trusted);
    }
    if (options_.recorder && k % options_.record_every == 0) {
      record_tick(*options_.recorder,
                  TickRecord{calc_recorded_tick_time(tick.t, config_.simulation.dt), tick.q, tick.qd, last_acceleration_,
                             tick.q_desired, tick.qd_desired, tick.qdd_desired, position, position_desired, command,
                             observed_size()});
    }
    laps.lap(&TickClock::statistics);
  }

  /// Steps the plant over the tick; `applied_torque` is the torque averaged over it.
  std::optional<PassResult> step_plant(const TickState& tick, const ControlCommand& command, const FeedForwardTerm& feed_forward,
                                       Eigen::VectorXd& applied_torque) {
    try {
      applied_torque = step_tick(plant_, *options_.controller, command, feed_forward.torque,
                                 DesiredState{tick.q_desired, tick.qd_desired, tick.qdd_desired}, config_.simulation.dt,
                                 setup_.pd_substeps(), options_);
    } catch (const std::exception& failure) {
      return diverged(tick.t, std::string("integrator failed: ") + failure.what());
    }
    simulated_ = static_cast<double>(++steps_) * config_.simulation.dt;
    return std::nullopt;
  }

  /// Measures the new state, and learns (or collects) the tick's sample: x = (q, q̇, q̈) measured
  /// at the tick's start with q̈ the backward difference over it (the thesis's), y = the torque.
  std::optional<PassResult> learn(const Eigen::VectorXd& applied_torque) {
    const Measurement next = measure(plant_, options_);
    const Eigen::VectorXd qdd_measured = (next.qd - measured_.qd) / config_.simulation.dt;
    if (!qdd_measured.allFinite()) return diverged(plant_.time(), "the state became NaN or Inf");
    last_acceleration_ = qdd_measured;
    if (options_.samples || options_.learner) {
      Sample sample{make_learner_input(measured_.q, measured_.qd, qdd_measured), applied_torque};
      if (options_.learner) {
        {
          ScopedSeconds timed(options_.clock ? &options_.clock->update_seconds : nullptr);
          options_.learner->update(sample.x, sample.y);
        }
        if (options_.clock) ++options_.clock->updates;
      }
      if (options_.samples) options_.samples->push_back(std::move(sample));
    }
    measured_ = next;
    return std::nullopt;
  }

  JobSetup& setup_;
  ArmSimulation& plant_;
  const JointTrajectory& trajectory_;
  const PassOptions& options_;
  const JobConfig& config_;
  DivergenceMonitor divergence_;
  double pass_start_ = 0.0;
  bool mismatch_present_ = false;
  std::size_t segment_ = 0;
  double simulated_ = 0.0;  // steps · dt, not a running sum of dt: 20 steps of 0.1 s are 2 s, not 2.0000000000000013
  long steps_ = 0;
  Eigen::VectorXd last_acceleration_;
  Measurement measured_;
  Eigen::VectorXd last_finite_q_;   // where a diverged pass's advice judges the steps
  Eigen::VectorXd last_desired_q_;
};

}  // namespace

PassResult run_control_pass(JobSetup& setup, ArmSimulation& plant, const JointTrajectory& trajectory, const PassOptions& options) {
  ControlPassRun pass(setup, plant, trajectory, options);
  for (int k = 0; k < trajectory.size(); ++k) {
    if (std::optional<PassResult> end = pass.run_tick(k)) return *end;
  }
  return pass.finish();
}

}  // namespace armfarm
