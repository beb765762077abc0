#include "engine/kinematics/serial_chain.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/trajectory/savitzky_golay.hpp"
#include "engine/trajectory/task_space_path.hpp"
#include "engine/trajectory/trajectory.hpp"
#include "engine/trajectory/trajectory_differentiation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

Eigen::VectorXd expand(const Eigen::VectorXd& values, int n, const Eigen::VectorXd& fallback, const char* field) {
  if (values.size() == 0) return fallback;
  if (values.size() == 1) return Eigen::VectorXd::Constant(n, values[0]);
  if (values.size() != n) {
    throw std::invalid_argument(std::string(field) + ": has " + std::to_string(values.size()) +
                                " values, expected 1 or one per active joint (" + std::to_string(n) + ")");
  }
  return values;
}

void fill_task_positions(JointTrajectory& trajectory, ArmDynamics& dynamics) {
  const SerialChain chain = make_end_effector_chain(dynamics);
  trajectory.task_position.resize(trajectory.q.rows(), 3);
  for (Eigen::Index k = 0; k < trajectory.q.rows(); ++k) {
    trajectory.task_position.row(k) = chain.calc_position(trajectory.q.row(k).transpose()).transpose();
  }
}

JointTrajectory build_sine(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt) {
  const int n = dynamics.dof();
  const JointRanges ranges{dynamics.lower_limits(), dynamics.upper_limits(), dynamics.velocity_limits()};
  const SineTrajectoryConfig sine = resolve_sine_defaults(config.sine, n, dynamics.start_positions(), &ranges);
  const Eigen::VectorXd& amplitude = sine.amplitude;
  const Eigen::VectorXd& frequency = sine.frequency;
  const Eigen::VectorXd& phase = sine.phase;
  const Eigen::VectorXd& offset = sine.offset;
  if (!(sine.duration > 0.0)) throw std::invalid_argument("trajectory.sine.duration: must be positive");
  if ((frequency.array() < 0.0).any()) throw std::invalid_argument("trajectory.sine.frequency: must not be negative");
  const int samples = std::max(2, static_cast<int>(std::lround(sine.duration / dt)));
  JointTrajectory trajectory;
  trajectory.dt = dt;
  trajectory.q.resize(samples, n);
  trajectory.qd.resize(samples, n);
  trajectory.qdd.resize(samples, n);
  for (int k = 0; k < samples; ++k) {
    for (int j = 0; j < n; ++j) {
      const double omega = 2.0 * M_PI * frequency[j];
      const double angle = omega * k * dt + phase[j];
      trajectory.q(k, j) = offset[j] + amplitude[j] * std::sin(angle);
      trajectory.qd(k, j) = amplitude[j] * omega * std::cos(angle);
      trajectory.qdd(k, j) = -amplitude[j] * omega * omega * std::sin(angle);
    }
  }
  if (config.differentiation != Differentiation::analytic) fill_derivatives(trajectory, config.differentiation, false, 15, 3);
  // One segment per period of the slowest moving joint (for per-loop statistics).
  double slowest = 0.0;
  for (int j = 0; j < n; ++j) {
    if (amplitude[j] != 0.0 && frequency[j] > 0.0 && (slowest == 0.0 || frequency[j] < slowest)) slowest = frequency[j];
  }
  const int period = slowest > 0.0 ? static_cast<int>(std::lround(1.0 / (slowest * dt))) : samples;
  for (int start = 0; start < samples; start += std::max(1, period)) trajectory.segment_starts.push_back(start);
  fill_task_positions(trajectory, dynamics);
  return trajectory;
}

JointTrajectory build_recorded(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt) {
  const RecordedTrajectoryConfig& recorded = config.recorded;
  const std::string where = recorded.file.empty() ? "trajectory.recorded" : recorded.file;
  const int n = dynamics.dof();
  const int columns = recorded.task_space ? 3 : n;
  if (recorded.samples.cols() != columns) {
    throw std::invalid_argument(where + ": has " + std::to_string(recorded.samples.cols()) + " columns, expected " +
                                std::to_string(columns) + (recorded.task_space ? " (x, y, z)" : " (one per active joint)"));
  }
  if (recorded.samples.rows() < 2) throw std::invalid_argument(where + ": needs at least 2 samples");
  if (!(recorded.sample_rate > 0.0)) throw std::invalid_argument("trajectory.recorded.sample_rate: must be positive");
  if (recorded.loops < 1) throw std::invalid_argument("trajectory.recorded.loops: must be at least 1");
  // Resample to the control rate by linear interpolation.
  const int samples = calc_recorded_ticks(recorded, dt);
  Eigen::MatrixXd resampled(samples, columns);
  for (int k = 0; k < samples; ++k) {
    const double position = k * dt * recorded.sample_rate;
    const auto row = std::min<Eigen::Index>(static_cast<Eigen::Index>(position), recorded.samples.rows() - 2);
    const double fraction = position - static_cast<double>(row);
    resampled.row(k) = (1.0 - fraction) * recorded.samples.row(row) + fraction * recorded.samples.row(row + 1);
  }
  if (recorded.filter == RecordedFilter::savitzky_golay) {
    if (recorded.window < 3 || recorded.window % 2 == 0) throw std::invalid_argument("trajectory.recorded.window: must be odd and at least 3");
    if (recorded.polynomial_order < 2 || recorded.polynomial_order >= recorded.window) {
      throw std::invalid_argument("trajectory.recorded.polynomial_order: must be at least 2 and below the window");
    }
    if (const std::string problem = check_recorded_length(recorded, dt); !problem.empty()) throw std::invalid_argument(problem);
    resampled = calc_savitzky_golay(resampled, recorded.window, recorded.polynomial_order, 0, dt);
  } else if (recorded.filter == RecordedFilter::low_pass) {
    if (!(recorded.cutoff > 0.0)) throw std::invalid_argument("trajectory.recorded.cutoff: must be positive");
    resampled = calc_zero_phase_low_pass(resampled, recorded.cutoff, dt);
  }
  JointTrajectory trajectory;
  trajectory.dt = dt;
  const Eigen::MatrixXd joints =
      recorded.task_space ? calc_joint_path(dynamics, resampled, dynamics.start_positions(), where.c_str()) : resampled;
  trajectory.q = joints.replicate(recorded.loops, 1);
  for (int loop = 0; loop < recorded.loops; ++loop) trajectory.segment_starts.push_back(loop * samples);
  const bool smooth_enough = samples >= recorded.window && recorded.window > recorded.polynomial_order;
  const Differentiation method = config.differentiation == Differentiation::analytic ? Differentiation::smoothed : config.differentiation;
  fill_derivatives(trajectory, smooth_enough || method != Differentiation::smoothed ? method : Differentiation::analytic, false,
                   recorded.window, recorded.polynomial_order);
  if (recorded.task_space) {
    trajectory.task_position = resampled.replicate(recorded.loops, 1);
  } else {
    fill_task_positions(trajectory, dynamics);
  }
  return trajectory;
}

}  // namespace

SineTrajectoryConfig resolve_sine_defaults(const SineTrajectoryConfig& sine, int n, const Eigen::VectorXd& start_positions,
                                           const JointRanges* ranges) {
  SineTrajectoryConfig resolved = sine;
  resolved.frequency = expand(sine.frequency, n, Eigen::VectorXd::Constant(n, 0.25), "trajectory.sine.frequency");
  resolved.phase = expand(sine.phase, n, Eigen::VectorXd::Zero(n), "trajectory.sine.phase");
  resolved.offset = expand(sine.offset, n, start_positions, "trajectory.sine.offset");
  Eigen::VectorXd amplitude = Eigen::VectorXd::Constant(n, 0.3);
  if (sine.amplitude.size() == 0 && ranges && ranges->lower.size() == n && ranges->upper.size() == n && ranges->velocity.size() == n) {
    for (int j = 0; j < n; ++j) {
      const double room = std::min(resolved.offset[j] - ranges->lower[j], ranges->upper[j] - resolved.offset[j]);
      amplitude[j] = std::min(amplitude[j], std::max(0.0, kSineRangeShare * room));
      const double omega = 2.0 * M_PI * resolved.frequency[j];
      if (omega > 0.0 && std::isfinite(ranges->velocity[j]) && ranges->velocity[j] > 0.0) {
        amplitude[j] = std::min(amplitude[j], kSineVelocityShare * ranges->velocity[j] / omega);
      }
    }
  }
  resolved.amplitude = expand(sine.amplitude, n, amplitude, "trajectory.sine.amplitude");
  return resolved;
}

namespace {

JointTrajectory build_exact_trajectory(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt, std::uint64_t seed) {
  switch (config.kind) {
    case TrajectoryKind::sine: return build_sine(config, dynamics, dt);
    case TrajectoryKind::figure_eight: return build_figure_eight(config.figure_eight, config.differentiation, dynamics, dt);
    case TrajectoryKind::reaching: return build_reaching(config.reaching, config.differentiation, dynamics, dt, seed);
    case TrajectoryKind::recorded: return build_recorded(config, dynamics, dt);
  }
  throw std::invalid_argument("trajectory.kind: unknown kind");
}

bool is_solved_by_ik(const TrajectoryConfig& config) {
  return config.kind == TrajectoryKind::figure_eight || config.kind == TrajectoryKind::reaching ||
         (config.kind == TrajectoryKind::recorded && config.recorded.task_space);
}

}  // namespace

JointTrajectory build_trajectory(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt, std::uint64_t seed) {
  if (!(dt > 0.0)) throw std::invalid_argument("dt: must be positive");
  JointTrajectory trajectory = build_exact_trajectory(config, dynamics, dt, seed);
  if (config.ik_noise > 0.0 && is_solved_by_ik(config)) {
    RandomStream noise(seed, "trajectory.ik_noise");
    for (Eigen::Index k = 0; k < trajectory.q.rows(); ++k) {
      for (Eigen::Index j = 0; j < trajectory.q.cols(); ++j) trajectory.q(k, j) += noise.normal(0.0, config.ik_noise);
    }
    // Savitzky–Golay (smoothed): a recording's own window, else the sine's 15 ticks, order 3.
    const bool recorded = config.kind == TrajectoryKind::recorded;
    fill_derivatives(trajectory, config.differentiation, false, recorded ? config.recorded.window : 15,
                     recorded ? config.recorded.polynomial_order : 3);
  }
  return trajectory;
}

}  // namespace armfarm
