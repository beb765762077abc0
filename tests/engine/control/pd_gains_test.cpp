// The default gains' placement on the arm (engine/control/pd_gains.hpp): the gravity floor and
// the placement inertia. A one-joint inverted pendulum (a point-like bob of mass m at l above a
// horizontal pin, upright at q = 0) has the closed form: g(q) = −m·g0·l·sin q, its stiffness
// ∂g/∂q = −m·g0·l·cos q, and under PD τ = −kp q − kd q̇ the upright posture is held iff
// kp > m·g0·l. The simulation (ArmSimulation, RK4, PD at 1 ms) falls 2 % below that bound and
// holds 2 % above it (below, it leaves the upright posture for a sagged equilibrium); the floor
// (margin 2) lifts a controller scaled far below it to 2·m·g0·l, where it holds.
#include "engine/control/pd_gains.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "support/test_arms.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace armfarm {
namespace {

constexpr double kMass = 1.0, kLength = 0.5, kGravity = 9.81, kBobInertia = 0.001;

/// The bob about its own COM carries kBobInertia about each axis; the pin turns about x.
ArmModel make_inverted_pendulum() {
  return testing::make_one_link_arm("inverted pendulum", kMass, Eigen::Vector3d(0.0, 0.0, kLength),
                                    Eigen::Vector3d::Constant(kBobInertia).asDiagonal(), Eigen::Vector3d::UnitX());
}

constexpr double kStiffness = kMass * kGravity * kLength;  // |∂g/∂q| upright, N·m/rad

/// The largest |q| over `seconds` from q = 0.01 rad at rest under τ = −kp q − kd q̇ held per 1 ms.
double simulate_largest_angle(const ArmModel& model, double kp, double kd, double seconds) {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_4;
  options.soft_joint_limits = false;
  ArmSimulation plant(model, options);
  plant.set_state(0.0, Eigen::VectorXd::Constant(1, 0.01), Eigen::VectorXd::Zero(1));
  double largest = 0.01;
  const double h = 0.001;
  for (int k = 0; k < static_cast<int>(seconds / h); ++k) {
    plant.step(Eigen::VectorXd::Constant(1, -kp * plant.q()[0] - kd * plant.qd()[0]), h);
    largest = std::max(largest, std::fabs(plant.q()[0]));
    if (largest > 1.0) break;  // fallen
  }
  return largest;
}

TEST(GravityStiffness, EqualsTheClosedFormOfTheInvertedPendulum) {
  const ArmModel model = make_inverted_pendulum();
  ArmDynamics dynamics(model);
  for (double q : {0.0, 0.3, -1.1, 2.0}) {
    const Eigen::MatrixXd h = make_gravity_stiffness(dynamics, Eigen::VectorXd::Constant(1, q));
    ASSERT_EQ(h.rows(), 1);
    EXPECT_NEAR(h(0, 0), -kStiffness * std::cos(q), 1e-7 * kStiffness) << "q = " << q;
    // The torque itself, for the sign: holding the pole at q > 0 takes g(q) = −m·g0·l·sin q.
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
    EXPECT_NEAR(dynamics.calc_inverse_dynamics(Eigen::VectorXd::Constant(1, q), zero, zero)[0], -kStiffness * std::sin(q), 1e-9);
  }
}

TEST(GravityFloor, TheUprightPoleIsHeldJustAboveItsStiffnessAndFallsJustBelow) {
  const ArmModel model = make_inverted_pendulum();
  const double kd = 0.1;  // N·m·s/rad: M = m·l² + 0.001 = 0.251 kg·m², kd·h/M = 4e-4
  // Below: the upright posture is lost, and the pole sags to where kp·q = m·g0·l·sin q (0.35 rad).
  EXPECT_GT(simulate_largest_angle(model, 0.98 * kStiffness, kd, 15.0), 0.1);
  EXPECT_LT(simulate_largest_angle(model, 1.02 * kStiffness, kd, 15.0), 0.0101);  // held
}

TEST(GravityFloor, LiftsAScaledControllerToTwiceTheStiffnessAndItHolds) {
  const ArmModel model = make_inverted_pendulum();
  ArmDynamics dynamics(model);
  const double inertia = dynamics.calc_mass_matrix(Eigen::VectorXd::Zero(1))(0, 0);
  EXPECT_NEAR(inertia, kMass * kLength * kLength + kBobInertia, 1e-12);
  ControlConfig control;  // mass_bandwidth: kp = 400·M = 100.4, kd = 40·M
  const PdGains placed = calc_pd_gains(control, Eigen::VectorXd::Constant(1, inertia), {1});
  const double scale = 0.02;  // kp·s = 2.0 N·m/rad, below the 4.905 the pole needs
  ASSERT_LT(placed.kp[0] * scale, kStiffness);
  EXPECT_GT(simulate_largest_angle(model, placed.kp[0] * scale, placed.kd[0] * scale, 15.0), 0.5);

  std::vector<Eigen::MatrixXd> stiffness;
  for (double q : {0.0, 0.2, -0.2}) stiffness.push_back(make_gravity_stiffness(dynamics, Eigen::VectorXd::Constant(1, q)));
  const Eigen::VectorXd floor = calc_gravity_kp_floor(stiffness, 1);
  EXPECT_NEAR(floor[0], kGravityStiffnessMargin * kStiffness, 1e-6);  // the upright posture's, the largest
  const PdGains floored = calc_floored_gains(placed, floor, scale);
  EXPECT_NEAR(floored.kp[0] * scale, floor[0], 1e-12);
  // kd grows by √ of kp's factor: the placement's damping ratio kd / (2·√(kp·M)) is kept.
  EXPECT_NEAR(floored.kd[0] / std::sqrt(floored.kp[0]), placed.kd[0] / std::sqrt(placed.kp[0]), 1e-12);
  EXPECT_LT(simulate_largest_angle(model, floored.kp[0] * scale, floored.kd[0] * scale, 15.0), 0.0101);
}

TEST(GravityFloor, LeavesGainsAboveItUnchangedBitForBit) {
  const PdGains gains{Eigen::Vector3d(100.0, 3.0, 0.1), Eigen::Vector3d(10.0, 0.3, 0.01)};
  const Eigen::VectorXd floor = Eigen::Vector3d(1.0, 1.0, 0.0);
  const PdGains floored = calc_floored_gains(gains, floor, 0.2);  // joint 2: 0.6 < 1 is lifted
  EXPECT_EQ(floored.kp[0], gains.kp[0]);
  EXPECT_EQ(floored.kd[0], gains.kd[0]);
  EXPECT_EQ(floored.kp[2], gains.kp[2]);
  EXPECT_EQ(floored.kd[2], gains.kd[2]);
  EXPECT_NEAR(floored.kp[1], 5.0, 1e-12);
  EXPECT_NEAR(floored.kd[1], 0.3 * std::sqrt(5.0 / 3.0), 1e-12);
  // No floor, or no gains to scale: as given.
  EXPECT_EQ(calc_floored_gains(gains, Eigen::VectorXd(), 0.2).kp, gains.kp);
  EXPECT_EQ(calc_floored_gains(gains, floor, 0.0).kp, gains.kp);
}

TEST(GravityFloor, TheRowSumBoundsTheCoupledStiffnessByGershgorin) {
  // A symmetric, destabilising H with strong coupling: Kp at the floor keeps Kp + H positive
  // definite with every eigenvalue ≥ (1 − 1/margin)·min kp.
  Eigen::Matrix3d h;
  h << -3.0, 2.0, -1.0, 2.0, -0.5, 1.5, -1.0, 1.5, -0.2;
  const Eigen::VectorXd floor = calc_gravity_kp_floor({h}, 3);
  EXPECT_NEAR(floor[0], 12.0, 1e-12);
  EXPECT_NEAR(floor[1], 8.0, 1e-12);
  EXPECT_NEAR(floor[2], 5.4, 1e-12);
  const Eigen::Matrix3d held = Eigen::Matrix3d(floor.asDiagonal()) + h;
  const double lowest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(held).eigenvalues().minCoeff();
  EXPECT_GE(lowest, (1.0 - 1.0 / kGravityStiffnessMargin) * floor.minCoeff());
}

TEST(PlacementInertia, RaisesOnlyJointsWhoseInertiaGrowsBeyondTheRatio) {
  const Eigen::Vector3d start(0.008, 1.0, 0.5);
  const Eigen::Vector3d largest(0.23, 1.3, kPlacementInertiaRatio * 0.5);  // 29×, 1.3×, exactly the ratio
  const Eigen::VectorXd inertia = calc_placement_inertia(start, largest);
  EXPECT_NEAR(inertia[0], 0.23 / kPlacementInertiaRatio, 1e-15);
  EXPECT_EQ(inertia[1], start[1]);
  EXPECT_EQ(inertia[2], start[2]);
}

}  // namespace
}  // namespace armfarm
