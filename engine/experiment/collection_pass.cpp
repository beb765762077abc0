#include "engine/experiment/collection_pass.hpp"

#include "engine/experiment/job_steps.hpp"

#include <cmath>
#include <string>

namespace armfarm {

PassResult collect_samples(JobSetup& setup, ArmSimulation& plant, const CollectionPlan& plan, std::vector<Sample>& samples,
                           const std::function<bool()>& should_stop) {
  const LearningConfig& learning = setup.config().learning;
  const ControlConfig& control = setup.config().control;
  const double scale = calc_collect_gain_scale(setup.config());
  const CompositeController collector(ControlMode::feedback, setup.gains_at(scale), scale, calc_kd_scale(scale, control.keep_damping_ratio),
                                      setup.nominal().effort_limits(), control.limit_torque);
  RandomStream start_draws(setup.config().seed, std::string(plan.purpose) + ".start_state");
  RandomStream noise(setup.config().seed, std::string(plan.purpose) + ".sensor_noise");
  PassOptions options;
  options.controller = &collector;
  options.samples = &samples;
  options.noise = &noise;
  options.noise_qd = learning.collect_noise_qd;
  options.should_stop = should_stop;
  // Two independent normal noises on the angles add as one of the root-sum-square std.
  const double repeat_noise_q = std::hypot(learning.collect_noise_q, learning.collect_repeat_noise_q);
  PassResult total;
  for (int repeat = 0; repeat < plan.repeats; ++repeat) {
    options.noise_q = repeat > 0 ? repeat_noise_q : learning.collect_noise_q;
    options.start_offset = Eigen::VectorXd::Zero(setup.dof());
    if (repeat > 0 && learning.collect_start_spread > 0.0) {
      for (int j = 0; j < setup.dof(); ++j) options.start_offset[j] = start_draws.normal(0.0, learning.collect_start_spread);
    }
    const PassResult pass = run_control_pass(setup, plant, *plan.trajectory, options);
    total.simulated_seconds += pass.simulated_seconds;
    total.end_time = pass.end_time;
    if (!pass.ok()) {
      PassResult failed = pass;
      failed.simulated_seconds = total.simulated_seconds;
      return failed;
    }
  }
  return total;
}

}  // namespace armfarm
