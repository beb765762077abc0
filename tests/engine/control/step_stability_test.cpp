// The step-stability criterion (engine/control/step_stability.hpp) against the plant armfarm
// simulates. A one-joint turntable (a link spinning about the vertical: no gravity torque,
// M = I_zz + armature exactly) has the closed form of the criterion: under a PD held over
// h, with no damping, it is stable iff kd·h/M < 2 and kp·h²/M < 2·kd·h/M; its passive decay
// under RK4 iff b·h_i/M < 2.7853. Each bound is approached from both sides (2 % inside, 2 %
// outside) in the simulation (ArmSimulation, RK4, the PD computed once per period and held),
// and the criterion must call the same side stable.
#include "engine/control/step_stability.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace armfarm {
namespace {

/// A link on a vertical pin: COM on the axis, I_zz = `inertia`, plus `armature` and `damping`.
ArmModel make_turntable(double inertia, double armature, double damping) {
  return testing::make_one_link_arm("turntable", 1.0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.5, inertia).asDiagonal(),
                                    Eigen::Vector3d::UnitZ(), armature, damping);
}

struct PdRun {
  double start_error = 0.0;
  double end_error = 0.0;  ///< |q| + h·|q̇| after the run (inf when it blew up)
};

/// `periods` PD periods of h from q = 0.01 rad at rest: τ = −kp q − kd q̇ held over each period,
/// RK4 in `steps` steps per period.
PdRun simulate(const ArmModel& model, double kp, double kd, double h, int steps, int periods) {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_4;
  options.steps_per_tick = steps;
  options.soft_joint_limits = false;
  ArmSimulation plant(model, options);
  plant.set_state(0.0, Eigen::VectorXd::Constant(1, 0.01), Eigen::VectorXd::Zero(1));
  PdRun run{0.01, 0.0};
  for (int k = 0; k < periods; ++k) {
    const double tau = -kp * plant.q()[0] - kd * plant.qd()[0];
    try {
      plant.step(Eigen::VectorXd::Constant(1, tau), h);
    } catch (const std::runtime_error&) {
      run.end_error = std::numeric_limits<double>::infinity();
      return run;
    }
    if (!(std::fabs(plant.q()[0]) < 1e6)) {
      run.end_error = std::numeric_limits<double>::infinity();
      return run;
    }
  }
  run.end_error = std::fabs(plant.q()[0]) + h * std::fabs(plant.qd()[0]);
  return run;
}

/// Simulated growth of the error: stable runs shrink it by orders of magnitude, unstable ones grow it.
bool converged(const PdRun& run) { return run.end_error < 1e-3 * run.start_error; }
bool diverged(const PdRun& run) { return !(run.end_error < 1e3 * run.start_error); }

LoopStability judge(double inertia, double damping, double kp, double kd, double h, int steps) {
  const LoopPlant plant{Eigen::MatrixXd::Constant(1, 1, inertia), Eigen::VectorXd::Constant(1, damping)};
  const LoopGains gains{Eigen::VectorXd::Constant(1, kp), Eigen::VectorXd::Constant(1, kd)};
  return calc_loop_stability(plant, &gains, LoopSteps{h, 1, steps, true});
}

constexpr double kInertia = 0.02;   // kg·m²: I_zz 0.015 + armature 0.005
constexpr double kPeriod = 0.01;    // s

TEST(StepStability, DerivativeBoundKdHOverMOfTwoHoldsOnBothSides) {
  const ArmModel model = make_turntable(0.015, 0.005, 0.0);
  const double kp = 0.01 * kInertia / (kPeriod * kPeriod);  // kp·h²/M = 0.01, far inside its own bound
  for (const double ratio : {1.96, 2.04}) {
    const double kd = ratio * kInertia / kPeriod;
    const PdRun run = simulate(model, kp, kd, kPeriod, 1, 3000);
    const LoopStability criterion = judge(kInertia, 0.0, kp, kd, kPeriod, 1);
    EXPECT_NEAR(criterion.kd_ratio, ratio, 1e-12);
    if (ratio < 2.0) {
      EXPECT_TRUE(converged(run)) << "kd·h/M = " << ratio << ": error " << run.end_error;
      EXPECT_TRUE(criterion.stable()) << "ρ = " << criterion.spectral_radius;
    } else {
      EXPECT_TRUE(diverged(run)) << "kd·h/M = " << ratio << ": error " << run.end_error;
      EXPECT_FALSE(criterion.stable()) << "ρ = " << criterion.spectral_radius;
    }
    // Beyond the bound the closed form's eigenvalue near 1 − kd·h/M (kp ≈ 0) leads.
    if (ratio > 2.0) {
      EXPECT_NEAR(criterion.spectral_radius, ratio - 1.0, 0.01);
    }
  }
}

TEST(StepStability, ProportionalBoundTwiceKdHOverMHoldsOnBothSides) {
  const ArmModel model = make_turntable(0.015, 0.005, 0.0);
  const double c = 1.0;  // kd·h/M
  const double kd = c * kInertia / kPeriod;
  for (const double share : {0.98, 1.02}) {
    const double kp = share * 2.0 * c * kInertia / (kPeriod * kPeriod);  // kp·h²/M = share × 2·kd·h/M
    const PdRun run = simulate(model, kp, kd, kPeriod, 1, 3000);
    const LoopStability criterion = judge(kInertia, 0.0, kp, kd, kPeriod, 1);
    EXPECT_NEAR(criterion.kp_ratio, share * 2.0 * c, 1e-12);
    if (share < 1.0) {
      EXPECT_TRUE(converged(run)) << "kp·h²/M = " << share << " × bound: error " << run.end_error;
      EXPECT_TRUE(criterion.stable()) << "ρ = " << criterion.spectral_radius;
    } else {
      EXPECT_TRUE(diverged(run)) << "kp·h²/M = " << share << " × bound: error " << run.end_error;
      EXPECT_FALSE(criterion.stable()) << "ρ = " << criterion.spectral_radius;
    }
    // Closed form: the eigenvalues' product is det = 1 − c + a/2, so ρ = √det when complex.
    EXPECT_NEAR(criterion.spectral_radius, std::sqrt(1.0 - c + share * c), 1e-9);
  }
}

TEST(StepStability, RungeKuttaDampingBoundHoldsOnBothSides) {
  // No PD: the passive decay q̈ = −(b/M) q̇ under RK4 is multiplied by R(−b·h_i/M) per step.
  const double damping = 1.0;
  const ArmModel model = make_turntable(0.015, 0.005, damping);
  for (const double ratio : {0.98 * kRk4RealBound, 1.02 * kRk4RealBound}) {
    const double h = ratio * kInertia / damping;
    ArmSimulationOptions options;
    options.soft_joint_limits = false;
    ArmSimulation plant(model, options);
    plant.set_state(0.0, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, 1.0));
    bool blew_up = false;
    for (int k = 0; k < 1000 && !blew_up; ++k) {
      try {
        plant.step(Eigen::VectorXd::Zero(1), h);
      } catch (const std::runtime_error&) {
        blew_up = true;
      }
      blew_up = blew_up || !(std::fabs(plant.qd()[0]) < 1e6);
    }
    const LoopPlant passive{Eigen::MatrixXd::Constant(1, 1, kInertia), Eigen::VectorXd::Constant(1, damping)};
    const LoopStability criterion = calc_loop_stability(passive, nullptr, LoopSteps{h, 1, 1, true});
    EXPECT_NEAR(criterion.passive_step_ratio, ratio, 1e-12);
    if (ratio < kRk4RealBound) {
      EXPECT_FALSE(blew_up);
      EXPECT_LT(std::fabs(plant.qd()[0]), 1e-3) << "b·h_i/M = " << ratio;
      EXPECT_TRUE(criterion.stable());
    } else {
      EXPECT_TRUE(blew_up || std::fabs(plant.qd()[0]) > 1e3) << "b·h_i/M = " << ratio << ": q̇ " << plant.qd()[0];
      EXPECT_FALSE(criterion.stable());
    }
  }
}

TEST(StepStability, RungeKuttaRealBoundIsWhereTheAmplificationReachesOne) {
  const auto amplification = [](double z) { return 1.0 - z + z * z / 2.0 - z * z * z / 6.0 + z * z * z * z / 24.0; };
  EXPECT_NEAR(amplification(kRk4RealBound), 1.0, 1e-14);
  EXPECT_LT(amplification(kRk4RealBound * (1.0 - 1e-9)), 1.0);
  EXPECT_GT(amplification(kRk4RealBound * (1.0 + 1e-9)), 1.0);
}

TEST(StepStability, MoreIntegratorStepsBringTheDampedJointBackInside) {
  // b·dt/M = 5 at one step per tick (the armature-free wrist: b 0.5, M 0.001, 10 ms) is
  // outside RK4's region; the criterion asks for ceil(1.5 × 5 / 2.785) = 3 steps with its margin,
  // and the simulation at 2 steps (2.5 each, inside) decays.
  const double inertia = 0.001, damping = 0.5, dt = 0.01;
  const LoopPlant plant{Eigen::MatrixXd::Constant(1, 1, inertia), Eigen::VectorXd::Constant(1, damping)};
  const LoopGains gains{Eigen::VectorXd::Constant(1, inertia * 400.0), Eigen::VectorXd::Constant(1, inertia * 40.0)};
  EXPECT_FALSE(calc_loop_stability(plant, &gains, LoopSteps{dt, 1, 1, true}).stable());
  EXPECT_TRUE(calc_loop_stability(plant, &gains, LoopSteps{dt, 1, 2, true}).stable());
  const StepChoice choice = calc_stable_steps({plant}, {gains}, dt, true, 0, 0);
  EXPECT_TRUE(choice.found);
  EXPECT_EQ(choice.pd_substeps, 1);
  EXPECT_EQ(choice.integrator_steps, 3);
  // An explicit PD period is kept; the integrator steps follow it.
  const StepChoice held = calc_stable_steps({plant}, {gains}, dt, true, 2, 0);
  EXPECT_EQ(held.pd_substeps, 2);
  EXPECT_EQ(held.integrator_steps, 2);
  const ArmModel model = make_turntable(0.0005, 0.0005, damping);
  // (Overdamped by b: the slow pole is kp/(b + kd) = 0.74 /s, so it takes 30 s to settle.)
  EXPECT_TRUE(converged(simulate(model, gains.kp[0], gains.kd[0], dt, 2, 3000)));
  EXPECT_TRUE(diverged(simulate(model, gains.kp[0], gains.kd[0], dt, 1, 3000)));
}

TEST(StepStability, CoupledJointsAreJudgedOnTheirModesNotTheDiagonal) {
  // Two joints on one axis (M = [[I1 + I2, I2], [I2, I2]]): gains placed on the diagonal give
  // kd·h/M_jj = 0.8 on both, inside the bound, but the coupled loop's fastest mode has
  // λ_max(M⁻¹ diag(M)) = (1 + r) + √(r(1 + r)) = 3.41 for r = I2/I1 = 1: 2.7 > 2, unstable.
  const double i1 = 0.01, i2 = 0.01, h = 0.01;
  Eigen::Matrix2d mass;
  mass << i1 + i2, i2, i2, i2;
  const Eigen::Vector2d diagonal = mass.diagonal();
  const LoopPlant plant{mass, Eigen::Vector2d::Zero()};
  const LoopGains gains{diagonal * 4.0, diagonal * 0.8 / h};
  const LoopStability coupled = calc_loop_stability(plant, &gains, LoopSteps{h, 1, 1, true});
  EXPECT_NEAR(coupled.kd_ratio, 0.8, 1e-12);
  EXPECT_FALSE(coupled.stable());
  const LoopPlant decoupled{Eigen::Matrix2d(diagonal.asDiagonal()), Eigen::Vector2d::Zero()};
  EXPECT_TRUE(calc_loop_stability(decoupled, &gains, LoopSteps{h, 1, 1, true}).stable());
  // With the margin the fast mode needs 1.5 × 2.73 / P < 2, so P = 3.
  const StepChoice choice = calc_stable_steps({plant}, {gains}, h, true, 0, 0);
  EXPECT_TRUE(choice.found);
  EXPECT_EQ(choice.pd_substeps, 3);
}

TEST(StepStability, AdaptiveIntegratorsAreJudgedOnTheLoopAlone) {
  const LoopPlant plant{Eigen::MatrixXd::Constant(1, 1, 0.001), Eigen::VectorXd::Constant(1, 0.5)};
  const LoopGains gains{Eigen::VectorXd::Constant(1, 0.4), Eigen::VectorXd::Constant(1, 0.04)};
  const LoopStability adaptive = calc_loop_stability(plant, &gains, LoopSteps{0.01, 1, 1, false});
  EXPECT_EQ(adaptive.passive_step_ratio, 0.0);
  EXPECT_TRUE(adaptive.stable());
  EXPECT_EQ(calc_stable_steps({plant}, {gains}, 0.01, false, 0, 0).integrator_steps, 1);
}

}  // namespace
}  // namespace armfarm
