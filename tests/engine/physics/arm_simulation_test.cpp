// The stepped plant: its accelerations equal the exact forward dynamics, energy is conserved
// without damping, a payload adds its closed-form gravity torque, and sample-and-hold PD at
// the thesis's 10 ms tick is stable on the LWR thanks to the joints' armature.
#include "engine/physics/arm_simulation.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

namespace armfarm {
namespace {

TEST(ArmSimulation, MeasuredAccelerationEqualsForwardDynamicsWithArmature) {
  const ArmModel model = testing::load_lwr3();
  ArmSimulationOptions options;
  options.soft_joint_limits = false;
  options.friction_override.viscous = Eigen::VectorXd::Zero(7);
  ArmSimulation plant(model, options);
  ArmDynamics dynamics(model);
  const Eigen::VectorXd q = (Eigen::VectorXd(7) << 0.1, -0.6, 1.2, 1.0, 0.3, -0.2, 0.5).finished();
  const Eigen::VectorXd qd = (Eigen::VectorXd(7) << 0.3, -0.2, 0.1, 0.4, -0.5, 0.2, 0.1).finished();
  const Eigen::VectorXd tau = (Eigen::VectorXd(7) << 5, -20, 3, 8, -1, 0.5, 0.2).finished();
  plant.set_state(0.0, q, qd);
  plant.step(tau, 1e-9);  // hold tau; the state barely moves
  const Eigen::VectorXd expected = dynamics.calc_forward_dynamics(plant.q(), plant.qd(), tau);
  EXPECT_LE((plant.qdd() - expected).norm(), 1e-6 * expected.norm());
}

TEST(ArmSimulation, PassiveSwingConservesEnergy) {
  const ArmModel model = testing::load_lwr3();
  ArmSimulationOptions options;
  options.soft_joint_limits = false;
  options.accuracy = 1e-6;
  options.friction_override.viscous = Eigen::VectorXd::Zero(7);
  options.friction_override.coulomb = Eigen::VectorXd::Zero(7);
  ArmSimulation plant(model, options);
  plant.set_state(0.0, (Eigen::VectorXd(7) << 0, 0.3, 0, 0.4, 0, 0.3, 0).finished(), Eigen::VectorXd::Zero(7));
  const double start = plant.calc_energy();
  double worst = 0.0;
  for (int tick = 0; tick < 1000; ++tick) {  // 10 s
    plant.step(Eigen::VectorXd::Zero(7), 0.01);
    worst = std::max(worst, std::fabs(plant.calc_energy() - start));
  }
  // Scale: the arm's weight times its reach, ≈ 13.8 kg · 9.81 m/s² · 1 m ≈ 135 J. The integrator
  // bounds each step's local error by 1e-6 relative; over ~10³ steps drift stays below 1e-4 of that.
  EXPECT_LT(worst, 1e-4 * 135.0) << "energy drift " << worst << " J";
  EXPECT_GT(plant.integrator_steps(), 100);
}

TEST(ArmSimulation, PayloadAddsItsGravityTorque) {
  const ArmModel model = testing::load_lwr3();
  ArmSimulationOptions options;
  options.active_joints = {1};  // the shoulder pitch, all else locked at the start posture
  ArmDynamics nominal(model, options.active_joints);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.4);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  // Static torque: with the payload, the plant needs m·g·(horizontal lever) more to hold still.
  options.payload.mass = 2.0;
  ArmSimulation plant(model, options);
  plant.set_state(0.0, q, zero);
  const Eigen::VectorXd hold_nominal = nominal.calc_inverse_dynamics(q, zero, zero);
  plant.step(hold_nominal, 1e-9);
  const double qdd = plant.qdd()[0];
  const Eigen::Matrix3Xd jacobian = nominal.calc_end_effector_jacobian(q);
  const double extra_torque = -2.0 * (-9.81) * jacobian(2, 0);  // τ = −Jᵀ·(m g)
  const double mass = nominal.calc_mass_matrix(q)(0, 0);
  // The extra torque is unbalanced: (M + m·|J|²)·q̈ = −extra.
  const double lever_inertia = 2.0 * jacobian.col(0).squaredNorm();
  EXPECT_NEAR(qdd, -extra_torque / (mass + lever_inertia), 1e-6 * std::fabs(qdd) + 1e-9);
  EXPECT_LT(std::fabs(jacobian(2, 0)), 1.0);
  EXPECT_GT(std::fabs(extra_torque), 1.0);
}

// Sample-and-hold PD (+ optional exact feed-forward) at 10 ms. Gains place each joint's
// closed loop at 20 rad/s, critically damped, on the diagonal of the mass matrix at the
// start posture (the controller's default rule); appendix D's own gains are unstable under
// a 10 ms hold on the light wrist joints (kd·dt / inertia > 2).
double run_pd(double gain_scale, bool feed_forward, double seconds, double* sim_per_wall) {
  const ArmModel model = testing::load_lwr3();
  ArmSimulation plant(model, ArmSimulationOptions{});
  ArmDynamics dynamics(model);
  const Eigen::VectorXd start = dynamics.start_positions();
  const Eigen::VectorXd inertia = dynamics.calc_mass_matrix(start).diagonal();
  const double bandwidth = 20.0;
  const Eigen::VectorXd kp = inertia * bandwidth * bandwidth * gain_scale;
  const Eigen::VectorXd kd = inertia * 2.0 * bandwidth * gain_scale;
  plant.set_state(0.0, start, Eigen::VectorXd::Zero(7));
  Eigen::VectorXd q_d(7), qd_d(7), qdd_d(7);
  auto desired = [&](double t) {
    const double w = 2 * M_PI * 0.25;
    for (int j = 0; j < 7; ++j) {
      q_d[j] = start[j] + 0.3 * std::sin(w * t);
      qd_d[j] = 0.3 * w * std::cos(w * t);
      qdd_d[j] = -0.3 * w * w * std::sin(w * t);
    }
  };
  const double dt = 0.01;
  double worst = 0.0;
  const auto wall_start = std::chrono::steady_clock::now();
  for (int tick = 0; tick * dt < seconds; ++tick) {
    desired(tick * dt);
    Eigen::VectorXd tau = kp.cwiseProduct(q_d - plant.q()) + kd.cwiseProduct(qd_d - plant.qd());
    if (feed_forward) tau += dynamics.calc_inverse_dynamics(q_d, qd_d, qdd_d);
    plant.step(tau, dt);
    if (!plant.q().allFinite()) return INFINITY;
    desired((tick + 1) * dt);
    worst = std::max(worst, (plant.q() - q_d).cwiseAbs().maxCoeff());
  }
  if (sim_per_wall) {
    *sim_per_wall = seconds / std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  }
  return worst;
}

TEST(ArmSimulation, SampleAndHoldPdIsStableAtTenMilliseconds) {
  double speed = 0.0;
  const double computed_torque_error = run_pd(1.0, true, 4.0, &speed);
  EXPECT_LT(computed_torque_error, 0.015) << "PD + exact feed-forward, gain scale 1";
  const double low_gain_error = run_pd(0.2, true, 4.0, nullptr);
  EXPECT_LT(low_gain_error, 0.05) << "PD + exact feed-forward, gain scale 0.2";
  const double feedback_only = run_pd(0.2, false, 4.0, nullptr);
  EXPECT_TRUE(std::isfinite(feedback_only));
  EXPECT_GT(feedback_only, 5.0 * low_gain_error) << "low-gain feedback alone sags under gravity";
  EXPECT_LT(feedback_only, 0.5) << "but stays bounded";
  RecordProperty("sim_seconds_per_wall_second", std::to_string(speed));
  std::printf("PD+ID at gain 1: max error %.4f rad, %.1f simulated s per wall s\n", computed_torque_error, speed);
}

}  // namespace
}  // namespace armfarm
