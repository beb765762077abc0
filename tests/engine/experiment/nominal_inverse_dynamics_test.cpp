// control.feed_forward "analytic" is the nominal model's exact inverse dynamics: applied to the
// plant (no mismatch), it produces the desired acceleration, friction and damping included.
// Checked against Simbody's own forward dynamics of the plant (an independent computation).
#include "engine/experiment/nominal_inverse_dynamics.hpp"
#include "engine/random/random_stream.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(NominalInverseDynamics, DrivesThePlantToTheDesiredAccelerationWithDampingAndFriction) {
  ArmModel model = testing::load_lwr3();
  RandomStream random(11, "test.nominal_inverse_dynamics");
  for (int index : model.movable_joints()) {
    model.joints[index].damping = 0.5 + random.uniform();   // N·m·s/rad
    model.joints[index].friction = 0.2 + random.uniform();  // N·m, the file's are 0
  }
  ArmSimulationOptions options;
  options.soft_joint_limits = false;  // limit springs are outside the inverse dynamics by design
  ArmSimulation plant(model, options);
  ArmDynamics nominal(model);
  const int n = nominal.dof();
  const Eigen::VectorXd lower = nominal.lower_limits(), upper = nominal.upper_limits();
  double worst = 0.0, worst_rigid_only = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(n), qd(n), qdd(n);
    for (int j = 0; j < n; ++j) {
      q[j] = lower[j] + (upper[j] - lower[j]) * (0.1 + 0.8 * random.uniform());
      qd[j] = 2.0 * random.uniform() - 1.0;  // rad/s, within tanh's transition for some ticks
      qdd[j] = 4.0 * random.uniform() - 2.0;
    }
    if (trial % 4 == 0) qd *= 0.005;  // slow: Coulomb friction in its smooth region
    const Eigen::VectorXd tau = calc_nominal_inverse_dynamics(nominal, q, qd, qdd, options.coulomb_velocity_scale);
    plant.step(tau, 1e-6);       // holds tau
    plant.set_state(0.0, q, qd);  // re-realises the acceleration at exactly (q, q̇) under tau
    worst = std::max(worst, (plant.qdd() - qdd).cwiseAbs().maxCoeff());
    // The rigid body alone (the old "analytic") misses the passive forces.
    plant.step(nominal.calc_inverse_dynamics(q, qd, qdd), 1e-6);
    plant.set_state(0.0, q, qd);
    worst_rigid_only = std::max(worst_rigid_only, (plant.qdd() - qdd).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(worst_rigid_only, 1e-3);
  std::printf("analytic feed-forward: max |q̈ − q̈_d| %.2e rad/s² (rigid body only: %.2e)\n", worst, worst_rigid_only);
}

}  // namespace
}  // namespace armfarm
