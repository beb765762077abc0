// Exact rigid-body calculations checked against independent computations: the textbook
// closed form of a planar 2-link arm, forward/inverse dynamics round trips, finite
// differences of forward kinematics, and mass-matrix identities; on the arm corpus
// (tests/data/arms), a recursive Newton–Euler written in the test on the URDF as urdfdom reads it.
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "recursive_newton_euler.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace armfarm {
namespace {

constexpr double kGravity = 9.81;

// τ = M(q)q̈ + C(q,q̇)q̇ + g(q) of the planar arm, derived by hand (Lagrange).
Eigen::Vector2d calc_planar_inverse_dynamics(const testing::PlanarArmParameters& p, const Eigen::Vector2d& q,
                                             const Eigen::Vector2d& qd, const Eigen::Vector2d& qdd) {
  const double c2 = std::cos(q[1]);
  const double h = p.mass2 * p.length1 * p.com2 * std::sin(q[1]);
  const double m11 = p.mass1 * p.com1 * p.com1 + p.inertia1 +
                     p.mass2 * (p.length1 * p.length1 + p.com2 * p.com2 + 2 * p.length1 * p.com2 * c2) + p.inertia2 +
                     p.armature1;
  const double m12 = p.mass2 * (p.com2 * p.com2 + p.length1 * p.com2 * c2) + p.inertia2;
  const double m22 = p.mass2 * p.com2 * p.com2 + p.inertia2 + p.armature2;
  const double g1 = (p.mass1 * p.com1 + p.mass2 * p.length1) * kGravity * std::cos(q[0]) +
                    p.mass2 * p.com2 * kGravity * std::cos(q[0] + q[1]);
  const double g2 = p.mass2 * p.com2 * kGravity * std::cos(q[0] + q[1]);
  return {m11 * qdd[0] + m12 * qdd[1] - h * (2 * qd[0] * qd[1] + qd[1] * qd[1]) + g1,
          m12 * qdd[0] + m22 * qdd[1] + h * qd[0] * qd[0] + g2};
}

TEST(ArmDynamics, PlanarArmMatchesTheClosedFormAtRandomStates) {
  for (double armature : {0.0, 0.7}) {
    testing::PlanarArmParameters parameters;
    parameters.armature1 = armature;
    parameters.armature2 = 0.5 * armature;
    const ArmModel model = testing::make_planar_arm(parameters);
    ArmDynamics dynamics(model);
    std::mt19937 generator(7);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI), rate(-3, 3), acceleration(-10, 10);
    for (int trial = 0; trial < 150; ++trial) {
      const Eigen::Vector2d q(angle(generator), angle(generator)), qd(rate(generator), rate(generator)),
          qdd(acceleration(generator), acceleration(generator));
      const Eigen::Vector2d expected = calc_planar_inverse_dynamics(parameters, q, qd, qdd);
      const Eigen::VectorXd tau = dynamics.calc_inverse_dynamics(q, qd, qdd);
      EXPECT_LE((tau - expected).norm(), 1e-9 * std::max(1.0, expected.norm())) << "trial " << trial;
    }
  }
}

TEST(ArmDynamics, EachCallSeesItsOwnStateWhateverTheCallsBeforeIt) {
  // Each call realizes only the kinematics it reads (not the whole system). A call must never
  // read caches left by an earlier call at another state: interleaved calls on one instance,
  // each kind after the others, give the bits a fresh instance gives at that state alone.
  const ArmModel model = testing::load_lwr3();
  ArmDynamics shared(model, {0, 1, 3});
  std::mt19937 generator(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  const auto draw = [&](double scale) {
    Eigen::VectorXd v(3);
    for (int j = 0; j < 3; ++j) v[j] = scale * unit(generator);
    return v;
  };
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = draw(1.5), qd = draw(2.0), qdd = draw(5.0), tau = draw(20.0);
    ArmDynamics fresh_id(model, {0, 1, 3}), fresh_fd(model, {0, 1, 3}), fresh_m(model, {0, 1, 3}), fresh_x(model, {0, 1, 3});
    const Eigen::VectorXd id = fresh_id.calc_inverse_dynamics(q, qd, qdd);
    const Eigen::VectorXd fd = fresh_fd.calc_forward_dynamics(q, qd, tau);
    const Eigen::MatrixXd m = fresh_m.calc_mass_matrix(q);
    const Eigen::Vector3d x = fresh_x.calc_end_effector_position(q);
    // On the shared instance each call follows calls at other states (the previous trial's).
    EXPECT_TRUE(shared.calc_inverse_dynamics(q, qd, qdd) == id) << "trial " << trial;
    EXPECT_TRUE(shared.calc_mass_matrix(-q) == fresh_m.calc_mass_matrix(-q)) << "trial " << trial;
    EXPECT_TRUE(shared.calc_forward_dynamics(q, qd, tau) == fd) << "trial " << trial;
    EXPECT_TRUE(shared.calc_inverse_dynamics(q, -qd, qdd) == fresh_id.calc_inverse_dynamics(q, -qd, qdd)) << "trial " << trial;
    EXPECT_TRUE(shared.calc_mass_matrix(q) == m) << "trial " << trial;
    EXPECT_TRUE(shared.calc_end_effector_position(q) == x) << "trial " << trial;
    // The velocities do matter (c(q, q̇) is quadratic in q̇: −q̇ gives the same torques, 2q̇ not).
    EXPECT_TRUE(shared.calc_inverse_dynamics(q, -qd, qdd) == id) << "trial " << trial;
    EXPECT_FALSE(shared.calc_inverse_dynamics(q, 2.0 * qd, qdd) == id) << "trial " << trial;
  }
}

TEST(ArmDynamics, InverseAndForwardDynamicsAreInversesOnTheLwr) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  ASSERT_EQ(dynamics.dof(), 7);
  std::mt19937 generator(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(7), qd(7), qdd(7);
    for (int j = 0; j < 7; ++j) {
      q[j] = 1.5 * unit(generator);
      qd[j] = 2 * unit(generator);
      qdd[j] = 5 * unit(generator);
    }
    const Eigen::VectorXd tau = dynamics.calc_inverse_dynamics(q, qd, qdd);
    const Eigen::VectorXd recovered = dynamics.calc_forward_dynamics(q, qd, tau);
    EXPECT_LE((recovered - qdd).norm(), 1e-9 * qdd.norm()) << "trial " << trial;
  }
}

TEST(ArmDynamics, MassMatrixIsSymmetricPositiveDefiniteWithArmatureOnTheDiagonal) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  const Eigen::VectorXd q = (Eigen::VectorXd(7) << 0.3, -0.5, 1.0, 1.2, -0.4, 0.6, 0.1).finished();
  const Eigen::MatrixXd mass = dynamics.calc_mass_matrix(q);
  EXPECT_LE((mass - mass.transpose()).norm(), 1e-12);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(mass).eigenvalues().minCoeff(), 0.0);
  // Column j of M is the inverse dynamics of a unit acceleration of joint j minus the gravity
  // torques (no velocity, so no Coriolis terms).
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(7);
  const Eigen::VectorXd gravity = dynamics.calc_inverse_dynamics(q, zero, zero);
  for (int j = 0; j < 7; ++j) {
    const Eigen::VectorXd column = dynamics.calc_inverse_dynamics(q, zero, Eigen::VectorXd::Unit(7, j)) - gravity;
    EXPECT_LE((column - mass.col(j)).norm(), 1e-10) << "column " << j;
  }
  // The last joint turns only the light tip: its diagonal entry is dominated by the armature.
  EXPECT_GE(mass(6, 6), model.joints[model.movable_joints()[6]].armature);
}

TEST(ArmDynamics, JacobianEqualsFiniteDifferencesOfForwardKinematics) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics dynamics(model);
  const Eigen::VectorXd q = (Eigen::VectorXd(7) << 0.2, -0.7, 0.9, 1.3, -0.3, 0.5, 0.4).finished();
  const Eigen::Matrix3Xd jacobian = dynamics.calc_end_effector_jacobian(q);
  const double step = 1e-6;
  for (int j = 0; j < 7; ++j) {
    Eigen::VectorXd plus = q, minus = q;
    plus[j] += step;
    minus[j] -= step;
    const Eigen::Vector3d difference =
        (dynamics.calc_end_effector_position(plus) - dynamics.calc_end_effector_position(minus)) / (2 * step);
    EXPECT_LE((difference - jacobian.col(j)).norm(), 1e-8) << "joint " << j;
  }
}

TEST(ArmDynamics, LockedJointsBehaveAsFixedJointsAtTheirStartAngles) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics subset(model, {1, 3});
  ASSERT_EQ(subset.dof(), 2);
  ArmModel fixed = model;
  const std::vector<int> movable = model.movable_joints();
  for (int index : {0, 2, 4, 5, 6}) fixed.joints[movable[index]].type = JointType::fixed;
  for (int index : {0, 2, 4, 5, 6}) fixed.joints[movable[index]].origin =
      fixed.joints[movable[index]].origin *
      Eigen::Isometry3d(Eigen::AngleAxisd(model.joints[movable[index]].start_position, model.joints[movable[index]].axis));
  ArmDynamics reference(fixed);
  ASSERT_EQ(reference.dof(), 2);
  const Eigen::Vector2d q(-0.4, 1.1), qd(0.5, -0.8), qdd(2.0, -1.0);
  EXPECT_LE((subset.calc_inverse_dynamics(q, qd, qdd) - reference.calc_inverse_dynamics(q, qd, qdd)).norm(), 1e-10);
  EXPECT_LE((subset.calc_end_effector_position(q) - reference.calc_end_effector_position(q)).norm(), 1e-12);
}

// Each arm of the corpus (and the planar arm): armfarm's inverse dynamics (the Simbody plant built
// by armfarm's URDF loader) against the test's own recursive Newton–Euler on urdfdom's reading of
// the same file, at 20 random states inside the joint limits, gravity on. The arms cover rotated
// joint frames (every 7-DOF arm), offset wrist axes (UR5e), products of inertia (Panda, Gen3,
// OpenManipulator-X), continuous joints (Gen3, planar2) and fixed frames with and without mass.
TEST(ArmCorpus, InverseDynamicsEqualsAnIndependentNewtonEuler) {
  const std::string arms = std::string(ARMFARM_TEST_DATA_DIR) + "/arms/";
  const std::vector<std::string> files = {arms + "ur5e.urdf",          arms + "kuka_iiwa14.urdf",
                                          arms + "franka_panda.urdf",  arms + "kinova_gen3.urdf",
                                          arms + "open_manipulator_x.urdf", std::string(ARMFARM_SOURCE_DIR) + "/models/planar2.urdf",
                                          std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf"};
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const ArmModel model = load_arm_model_file(file);
    const testing::RecursiveNewtonEuler reference(file);
    const std::vector<int> movable = model.movable_joints();
    ASSERT_EQ(reference.joint_names().size(), movable.size());
    for (std::size_t j = 0; j < movable.size(); ++j) ASSERT_EQ(reference.joint_names()[j], model.joints[movable[j]].name);
    const int n = static_cast<int>(movable.size());
    ArmDynamics dynamics(model);
    ASSERT_EQ(dynamics.dof(), n);
    RandomStream random(22, "corpus.inverse_dynamics");
    double worst = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd q(n), qd(n), qdd(n), armature(n);
      for (int j = 0; j < n; ++j) {
        const Joint& joint = model.joints[movable[j]];
        q[j] = joint.has_position_limits ? random.uniform(joint.lower, joint.upper) : random.uniform(-M_PI, M_PI);
        const double rate = std::isfinite(joint.velocity_limit) ? joint.velocity_limit : 3.0;
        qd[j] = random.uniform(-rate, rate);
        qdd[j] = random.uniform(-10.0, 10.0);
        armature[j] = joint.armature;  // (the LWR's, from its <transmission>: urdfdom does not read them)
      }
      const Eigen::VectorXd expected = reference.calc_torques(q, qd, qdd) + armature.cwiseProduct(qdd);
      const Eigen::VectorXd tau = dynamics.calc_inverse_dynamics(q, qd, qdd);
      const double error = (tau - expected).lpNorm<Eigen::Infinity>() / expected.lpNorm<Eigen::Infinity>();
      worst = std::max(worst, error);
      EXPECT_LE(error, 1e-9) << "trial " << trial << "\n armfarm " << tau.transpose() << "\n reference " << expected.transpose();
    }
    std::printf("%s: worst relative difference %.2g over 20 states\n", model.name.c_str(), worst);
  }
}

}  // namespace
}  // namespace armfarm
