#include "engine/experiment/control_pass.hpp"

#include "engine/experiment/divergence_advice.hpp"
#include "engine/experiment/divergence_monitor.hpp"
#include "engine/experiment/tick_recording.hpp"

#include <chrono>
#include <stdexcept>

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

}  // namespace

PassResult run_control_pass(JobSetup& setup, ArmSimulation& plant, const JointTrajectory& trajectory, const PassOptions& options) {
  const JobConfig& config = setup.config();
  const double dt = config.simulation.dt;
  const int n = setup.dof();
  const double pass_start = plant.time();
  bool mismatch_present = setup.mismatch_from_start();
  if (options.schedule_mismatch && !mismatch_present && setup.has_mismatch()) setup.remove_mismatch(plant);
  Eigen::VectorXd q_start = trajectory.q.row(0).transpose();
  if (options.start_offset.size()) q_start += options.start_offset;
  plant.set_state(pass_start, q_start, trajectory.qd.row(0).transpose());
  DivergenceMonitor divergence(config.divergence, setup.nominal().velocity_limits(), setup.joint_numbers());
  const auto observed_size = [&options]() -> std::size_t { return options.observed ? options.observed->size() : 0; };
  const int ticks = trajectory.size();
  const std::size_t segments = trajectory.segment_starts.size();
  std::size_t segment = 0;
  double simulated = 0.0;  // steps · dt, not a running sum of dt: 20 steps of 0.1 s are 2 s, not 2.0000000000000013
  long steps = 0;
  Eigen::VectorXd last_acceleration = Eigen::VectorXd::Zero(n);
  Measurement measured = measure(plant, options);
  Eigen::VectorXd last_finite_q = plant.q();  // where a diverged pass's advice judges the steps
  Eigen::VectorXd last_desired_q = last_finite_q;

  // Stage timing (TickClock): `lap(slot)` adds the time since the previous lap to `slot`.
  using Clock = std::chrono::steady_clock;
  TickClock* const tick_clock = options.tick_clock;
  Clock::time_point lap_start;
  const auto lap = [&](double TickClock::*slot) {
    if (!tick_clock) return;
    const Clock::time_point now = Clock::now();
    tick_clock->*slot += std::chrono::duration<double>(now - lap_start).count();
    lap_start = now;
  };

  for (int k = 0; k < ticks; ++k) {
    if (tick_clock) {
      lap_start = Clock::now();
      ++tick_clock->ticks;
    }
    const double t = plant.time();
    if (options.should_stop && options.should_stop()) return end_pass(JobStatus::timeout, t, "stopped before the end of the run", simulated);
    if (options.schedule_mismatch && !mismatch_present && t - pass_start >= config.mismatch.start_time - 1e-12) {
      setup.apply_mismatch(plant);
      mismatch_present = true;
    }
    if (segment + 1 < segments && k == trajectory.segment_starts[segment + 1]) {
      ++segment;
      if (options.statistics) options.statistics->start_segment(t, observed_size());
      if (options.on_segment_end) {
        PassResult checkpoint = options.on_segment_end(static_cast<int>(segment));
        if (!checkpoint.ok()) return end_pass(checkpoint.status, t, checkpoint.message, simulated);
        if (tick_clock) lap_start = Clock::now();  // a checkpoint's passes are not this tick's work
      }
    }
    const Eigen::VectorXd q_desired = trajectory.q.row(k).transpose();
    const Eigen::VectorXd qd_desired = trajectory.qd.row(k).transpose();
    const Eigen::VectorXd qdd_desired = trajectory.qdd.row(k).transpose();
    const Eigen::VectorXd q = plant.q();
    const Eigen::VectorXd qd = plant.qd();

    if (q.allFinite()) {
      last_finite_q = q;
      last_desired_q = q_desired;
    }
    if (auto reason = divergence.check(t, q, qd, q_desired)) {
      return end_pass(JobStatus::diverged, t, *reason + make_divergence_advice(setup, *options.controller, trajectory, last_finite_q, last_desired_q), simulated);
    }
    lap(&TickClock::control);

    FeedForwardTerm feed_forward{Eigen::VectorXd::Zero(n)};
    if (options.feed_forward) feed_forward = options.feed_forward->calc(q_desired, qd_desired, qdd_desired);
    lap(&TickClock::feed_forward);
    const ControlCommand command = options.controller->calc_command(q_desired, qd_desired, measured.q, measured.qd, feed_forward.torque);
    lap(&TickClock::control);

    if (options.statistics) {
      const Eigen::Vector3d position = setup.end_effector().calc_position(q);
      const Eigen::Vector3d position_desired = trajectory.task_position.row(k).transpose();
      options.statistics->add_tick(q_desired, q, position_desired, position, command);
      if (feed_forward.from_learner) {
        lap(&TickClock::statistics);
        const Eigen::VectorXd true_torque = setup.calc_true_torque(q_desired, qd_desired, qdd_desired, mismatch_present);
        lap(&TickClock::true_dynamics);
        options.statistics->add_model_accuracy(true_torque, feed_forward.torque, feed_forward.output_trusted);
      }
      if (options.recorder && k % options.record_every == 0) {
        record_tick(*options.recorder, TickRecord{calc_recorded_tick_time(t, dt), q, qd, last_acceleration, q_desired, qd_desired, qdd_desired, position,
                                                  position_desired, command, observed_size()});
      }
      lap(&TickClock::statistics);
    }

    Eigen::VectorXd applied_torque;  // averaged over the tick: the learner's target
    try {
      applied_torque = step_tick(plant, *options.controller, command, feed_forward.torque,
                                 DesiredState{q_desired, qd_desired, qdd_desired}, dt, setup.pd_substeps(), options);
    } catch (const std::exception& failure) {
      return end_pass(JobStatus::diverged, t,
                      std::string("integrator failed: ") + failure.what() +
                          make_divergence_advice(setup, *options.controller, trajectory, last_finite_q, last_desired_q),
                      simulated);
    }
    lap(&TickClock::physics);
    simulated = static_cast<double>(++steps) * dt;
    const Measurement next = measure(plant, options);
    const Eigen::VectorXd qdd_measured = (next.qd - measured.qd) / dt;  // the thesis's backward difference
    if (!qdd_measured.allFinite()) {
      return end_pass(JobStatus::diverged, plant.time(),
                      "the state became NaN or Inf" + make_divergence_advice(setup, *options.controller, trajectory, last_finite_q, last_desired_q),
                      simulated);
    }
    last_acceleration = qdd_measured;
    if (options.samples || options.learner) {
      Sample sample{make_learner_input(measured.q, measured.qd, qdd_measured), applied_torque};
      if (options.learner) {
        const auto start = std::chrono::steady_clock::now();
        options.learner->update(sample.x, sample.y);
        if (options.clock) {
          options.clock->update_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          ++options.clock->updates;
        }
      }
      if (options.samples) options.samples->push_back(std::move(sample));
    }
    measured = next;
    lap(&TickClock::learning);
  }
  if (options.statistics) options.statistics->end(observed_size());
  if (options.on_segment_end) {
    PassResult checkpoint = options.on_segment_end(static_cast<int>(segments));
    if (!checkpoint.ok()) return end_pass(checkpoint.status, plant.time(), checkpoint.message, simulated);
  }
  return end_pass(JobStatus::done, plant.time(), {}, simulated);
}

}  // namespace armfarm
