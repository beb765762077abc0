// The fixed-step runge_kutta_4 plant against a tight-accuracy reference (Simbody's adaptive
// Runge–Kutta–Merson at accuracy 1e-10, restarted every tick): the accuracy criterion of
// engine/README.md ("Integrator choice") is the largest joint-angle difference at any tick of a
// job, here the 7-DOF LWR III under sample-and-hold PD + exact feed-forward on a 0.3 rad sine
// and the 3-DOF arm driven into a soft joint limit; plus fourth-order convergence in the step
// and q̈ equal to the exact forward dynamics.
#include "engine/physics/arm_simulation.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace armfarm {
namespace {

ArmSimulationOptions reference_options() {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_merson;
  options.accuracy = 1e-10;
  return options;
}

ArmSimulationOptions fixed_step_options(int steps_per_tick) {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_4;
  options.steps_per_tick = steps_per_tick;
  return options;
}

/// Joint angles at every tick (rows) of sample-and-hold PD at 20 rad/s (critically damped on the
/// start posture's mass-matrix diagonal) + exact feed-forward, tracking `amplitude` rad at 0.25 Hz
/// about the start posture plus `bias` rad, for `seconds` at dt = 0.01.
Eigen::MatrixXd run_pd(const ArmModel& model, ArmSimulationOptions options, const std::vector<int>& active, double amplitude,
                       double bias, double seconds) {
  options.active_joints = active;
  ArmSimulation plant(model, options);
  ArmDynamics dynamics(model, active);
  const int n = dynamics.dof();
  const Eigen::VectorXd start = dynamics.start_positions();
  const Eigen::VectorXd inertia = dynamics.calc_mass_matrix(start).diagonal();
  const Eigen::VectorXd kp = inertia * 400.0, kd = inertia * 40.0;
  plant.set_state(0.0, start, Eigen::VectorXd::Zero(n));
  const double dt = 0.01, w = 2.0 * M_PI * 0.25;
  const int ticks = static_cast<int>(std::lround(seconds / dt));
  Eigen::MatrixXd angles(ticks, n);
  for (int k = 0; k < ticks; ++k) {
    const double t = k * dt;
    const Eigen::VectorXd q_d = start.array() + bias + amplitude * std::sin(w * t);
    const Eigen::VectorXd qd_d = Eigen::VectorXd::Constant(n, amplitude * w * std::cos(w * t));
    const Eigen::VectorXd qdd_d = Eigen::VectorXd::Constant(n, -amplitude * w * w * std::sin(w * t));
    const Eigen::VectorXd tau = kp.cwiseProduct(q_d - plant.q()) + kd.cwiseProduct(qd_d - plant.qd()) +
                                dynamics.calc_inverse_dynamics(q_d, qd_d, qdd_d);
    plant.step(tau, dt);
    angles.row(k) = plant.q().transpose();
  }
  return angles;
}

double max_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(FixedStepIntegrator, MatchesTightReferenceOnThePdJobWithinTheStatedTolerance) {
  const ArmModel model = testing::load_lwr3();
  const Eigen::MatrixXd reference = run_pd(model, reference_options(), {}, 0.3, 0.0, 4.0);
  const Eigen::MatrixXd fixed = run_pd(model, fixed_step_options(1), {}, 0.3, 0.0, 4.0);
  const double error = max_difference(fixed, reference);
  // The stated criterion (engine/README.md): at most 1e-5 rad at any tick of the job (measured
  // 2e-9 here, the adaptive default at 1e-5 gives 8e-10).
  EXPECT_LT(error, 1e-5) << "max joint-angle error " << error << " rad";
  // Not trivially equal: the arm moves by tenths of a radian.
  EXPECT_GT((reference.colwise().maxCoeff() - reference.colwise().minCoeff()).maxCoeff(), 0.3);
  ArmSimulationOptions adaptive;
  adaptive.integrator = IntegratorKind::runge_kutta_merson;
  std::printf("PD job: runge_kutta_4 %.3g rad, runge_kutta_merson at 1e-5 %.3g rad\n", error,
              max_difference(run_pd(model, adaptive, {}, 0.3, 0.0, 4.0), reference));
}

TEST(FixedStepIntegrator, ConvergesAtFourthOrderInTheStep) {
  const ArmModel model = testing::load_lwr3();
  const Eigen::MatrixXd reference = run_pd(model, reference_options(), {}, 0.3, 0.0, 1.0);
  const double coarse = max_difference(run_pd(model, fixed_step_options(1), {}, 0.3, 0.0, 1.0), reference);
  const double fine = max_difference(run_pd(model, fixed_step_options(2), {}, 0.3, 0.0, 1.0), reference);
  // Halving the step divides a fourth-order method's error by about 2⁴ = 16 (while above the
  // reference's own error).
  EXPECT_GT(coarse / fine, 8.0) << coarse << " vs " << fine;
  EXPECT_LT(coarse / fine, 32.0) << coarse << " vs " << fine;
}

TEST(FixedStepIntegrator, StaysWithinToleranceAgainstASoftJointLimit) {
  // 3-DOF arm (joints 1, 2, 4) commanded 0.3 rad beyond joint 4's upper limit: the stiff limit
  // spring-damper (2000 N·m/rad, 20 N·m·s/rad) takes over, and its damping switches on at the
  // limit, a jump a fixed step cannot resolve; those ticks go to the adaptive integrator.
  const ArmModel model = testing::load_lwr3();
  const std::vector<int> active = {0, 1, 3};
  ArmDynamics dynamics(model, active);
  const double bias = dynamics.upper_limits()[2] - dynamics.start_positions()[2] + 0.3;
  ASSERT_TRUE(std::isfinite(bias));
  const Eigen::MatrixXd reference = run_pd(model, reference_options(), active, 0.0, bias, 2.0);
  const double at_limit = reference.col(2).maxCoeff() - dynamics.upper_limits()[2];
  EXPECT_GT(at_limit, 1e-3) << "the run should press into the limit";
  const double error = max_difference(run_pd(model, fixed_step_options(1), active, 0.0, bias, 2.0), reference);
  ArmSimulationOptions adaptive;
  adaptive.integrator = IntegratorKind::runge_kutta_merson;
  const double adaptive_error = max_difference(run_pd(model, adaptive, active, 0.0, bias, 2.0), reference);
  std::printf("limit: runge_kutta_4 %.3g rad; runge_kutta_merson at 1e-5 %.3g rad\n", error, adaptive_error);
  // The criterion (engine/README.md): at most 1e-5 rad at any tick.
  EXPECT_LT(error, 1e-5);
}

TEST(FixedStepIntegrator, AccelerationEqualsForwardDynamicsWithArmature) {
  const ArmModel model = testing::load_lwr3();
  ArmSimulationOptions options = fixed_step_options(1);
  options.soft_joint_limits = false;
  options.friction_override.viscous = Eigen::VectorXd::Zero(7);
  options.friction_override.coulomb = Eigen::VectorXd::Zero(7);
  ArmSimulation plant(model, options);
  ArmDynamics dynamics(model);
  const Eigen::VectorXd q = (Eigen::VectorXd(7) << 0.1, -0.6, 1.2, 1.0, 0.3, -0.2, 0.5).finished();
  const Eigen::VectorXd qd = (Eigen::VectorXd(7) << 0.3, -0.2, 0.1, 0.4, -0.5, 0.2, 0.1).finished();
  const Eigen::VectorXd tau = (Eigen::VectorXd(7) << 5, -20, 3, 8, -1, 0.5, 0.2).finished();
  plant.set_state(0.0, q, qd);
  for (int k = 0; k < 3; ++k) plant.step(tau, 0.01);  // the reused first stage on ticks 2 and 3
  const Eigen::VectorXd expected = dynamics.calc_forward_dynamics(plant.q(), plant.qd(), tau);
  EXPECT_LE((plant.qdd() - expected).norm(), 1e-10 * expected.norm());
  EXPECT_NEAR(plant.time(), 0.03, 1e-15);
  EXPECT_EQ(plant.integrator_steps(), 3);
}

}  // namespace
}  // namespace armfarm
