#include "engine/experiment/divergence_advice.hpp"

#include "engine/control/step_stability.hpp"
#include "engine/experiment/job_steps.hpp"

#include <cmath>
#include <string>

namespace armfarm {
namespace {

/// rad: an error this large at divergence with stable steps means the arm was not held.
constexpr double kFarOff = 0.1;

/// The share of a velocity limit a slowed trajectory is aimed at.
constexpr double kSlowdownTarget = 0.8;

/// The key (and its new value) that slows the trajectory by `factor` (> 1).
std::string make_slowdown(const TrajectoryConfig& trajectory, double factor) {
  const auto scaled_integer = [&](int value) { return std::to_string(static_cast<long long>(std::ceil(value * factor))); };
  switch (trajectory.kind) {
    case TrajectoryKind::sine: {
      const Eigen::VectorXd& frequency = trajectory.sine.frequency;
      if (frequency.size() == 1) return "trajectory.sine.frequency to " + format_figure(frequency[0] / factor) + " Hz";
      if (frequency.size() == 0) return "trajectory.sine.frequency to " + format_figure(0.25 / factor) + " Hz";
      return "trajectory.sine.frequency (each ÷ " + format_figure(factor) + ")";
    }
    case TrajectoryKind::figure_eight:
      return "trajectory.figure_eight.points_per_loop to " + scaled_integer(trajectory.figure_eight.points_per_loop);
    case TrajectoryKind::reaching:
      return "trajectory.reaching.points_per_reach to " + scaled_integer(trajectory.reaching.points_per_reach);
    case TrajectoryKind::recorded:
      return "trajectory.recorded.sample_rate to " + format_figure(trajectory.recorded.sample_rate / factor) + " Hz";
  }
  return "the trajectory's speed";
}

}  // namespace

std::string make_divergence_advice(JobSetup& setup, const CompositeController& controller, const JointTrajectory& trajectory,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& q_desired) {
  const JobConfig& config = setup.config();
  const SimulationConfig& simulation = config.simulation;
  const bool fixed_step = simulation.integrator == IntegratorKind::runge_kutta_4;
  // (1) The steps, judged at the posture where the pass diverged.
  if (q.size() == setup.dof() && q.allFinite()) {
    const ArmDynamics& nominal = setup.nominal();
    const Eigen::MatrixXd mass = setup.nominal().calc_mass_matrix(q);
    const LoopPlant plant{mass, nominal.viscous_damping()};
    const LoopGains gains{controller.kp(), controller.kd()};
    const LoopStability ran =
        calc_loop_stability(plant, &gains, LoopSteps{simulation.dt, setup.pd_substeps(), setup.integrator_steps(), fixed_step});
    if (!ran.stable()) {
      const StepChoice fix = setup.calc_steps_at(q, controller);
      const int joint = setup.joint_numbers().at(static_cast<std::size_t>(ran.joint));
      std::string advice = "; the step-stability criterion calls the steps it ran with (pd_substeps " + std::to_string(setup.pd_substeps()) +
                           (fixed_step ? ", integrator_steps_per_tick " + std::to_string(setup.integrator_steps()) : std::string()) +
                           ") unstable at the posture where it diverged (joint " + std::to_string(joint) + ": " +
                           (ran.integrator_stable() ? "the PD loop grows ×" + format_figure(ran.spectral_radius) +
                                                          " per period, kd·h/M = " + format_figure(ran.kd_ratio) + ", of its fastest coupled mode " + format_figure(ran.modal_kd_ratio)
                                                    : "RK4's passive decay ratio " + format_figure(ran.passive_step_ratio) +
                                                          " is above its bound " + format_figure(kRk4RealBound)) +
                           ")";
      if (!fix.found) return advice + "; no steps within the keys' ranges are stable there: lower control.gain_scale or dt";
      if (fix.pd_substeps > setup.pd_substeps()) advice += "; set pd_substeps to " + std::to_string(fix.pd_substeps);
      if (fixed_step && fix.pd_substeps * fix.integrator_steps > setup.pd_substeps() * setup.integrator_steps()) {
        advice += std::string(fix.pd_substeps > setup.pd_substeps() ? " and" : "; set") + " integrator_steps_per_tick to " +
                  std::to_string(fix.integrator_steps);
      }
      return advice + " (stable there with the criterion's margin)";
    }
  }
  // (2) A desired motion faster than a joint's velocity limit.
  const Eigen::VectorXd limits = setup.nominal().velocity_limits();
  double worst = 0.0;
  int worst_joint = -1;
  for (Eigen::Index j = 0; j < trajectory.qd.cols(); ++j) {
    if (!(std::isfinite(limits[j]) && limits[j] > 0.0)) continue;
    const double ratio = trajectory.qd.col(j).cwiseAbs().maxCoeff() / limits[j];
    if (ratio > worst) {
      worst = ratio;
      worst_joint = static_cast<int>(j);
    }
  }
  if (worst > 1.0) {
    const int joint = setup.joint_numbers().at(static_cast<std::size_t>(worst_joint));
    return "; the desired motion asks joint " + std::to_string(joint) + " for " +
           format_figure(worst * limits[worst_joint]) + " rad/s, above its velocity limit " + format_figure(limits[worst_joint]) +
           " rad/s: set " + make_slowdown(config.trajectory, worst / kSlowdownTarget);
  }
  // (3) Far off the desired motion with stable steps: the feedback is too weak to hold the arm.
  if (q.size() == q_desired.size() && q.size() > 0 && q.allFinite()) {
    Eigen::Index worst_error = 0;
    const double error = (q - q_desired).cwiseAbs().maxCoeff(&worst_error);
    if (error > kFarOff) {
      return "; the arm is " + format_figure(error) + " rad off the desired motion (joint " +
             std::to_string(setup.joint_numbers().at(static_cast<std::size_t>(worst_error))) +
             ") with stable steps: the feedback is too weak to hold it — raise control.gain_scale (now " +
             format_figure(config.control.gain_scale) + ") or add a feed-forward (control.feed_forward)";
    }
  }
  // (4) Nothing computable: name the keys.
  return "; the step-stability criterion calls the steps stable where it diverged, so they are not the cause: other gains "
         "(control.gain_scale, now " + format_figure(config.control.gain_scale) + "; control.bandwidth, control.damping_ratio), "
         "a finer PD loop (pd_substeps " + std::to_string(2 * setup.pd_substeps()) + ") or the divergence.* bounds";
}

}  // namespace armfarm
