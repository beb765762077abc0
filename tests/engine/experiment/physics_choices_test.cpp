// Physics and control choices a job makes visible (issue 12): whether a gain scale keeps the
// damping ratio, and the armature switched per job. Checked against the closed form of the
// default gain rule kp = M_jj·ω², kd = 2ζ·M_jj·ω.
#include "engine/experiment/job_setup.hpp"
#include "../physics/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace armfarm {
namespace {

/// ζ = kd / (2·√(kp·M_jj)) of the controller's scaled gains, per joint.
Eigen::VectorXd calc_damping_ratios(JobSetup& setup) {
  const CompositeController controller = setup.make_controller();
  const Eigen::VectorXd inertia = setup.nominal().calc_mass_matrix(setup.nominal().start_positions()).diagonal();
  return controller.kd().array() / (2.0 * (controller.kp().array() * inertia.array()).sqrt());
}

TEST(PhysicsChoices, GainScaleKeepsTheDampingRatioOnlyWhenAsked) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.control.gain_scale = 0.2;
  JobSetup thesis(model, config);
  const Eigen::VectorXd dropped = calc_damping_ratios(thesis);
  config.control.keep_damping_ratio = true;
  JobSetup kept(model, config);
  const Eigen::VectorXd same = calc_damping_ratios(kept);
  for (int j = 0; j < dropped.size(); ++j) {
    EXPECT_NEAR(dropped[j], std::sqrt(0.2), 1e-12) << "joint " << j + 1;
    EXPECT_NEAR(same[j], 1.0, 1e-12) << "joint " << j + 1;
  }
  // kp is scaled alike either way.
  EXPECT_TRUE(thesis.make_controller().kp().isApprox(kept.make_controller().kp(), 1e-15));
  std::printf("gain scale 0.2: damping ratio %.3f (kd × 0.2) or %.3f (kd × √0.2)\n", dropped[0], same[0]);
}

TEST(PhysicsChoices, ArmatureScaleChangesTheMassMatrixDiagonalByTheArmature) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  JobSetup with(model, config);
  config.simulation.armature_scale = 0.0;
  JobSetup without(model, config);
  const Eigen::VectorXd q = with.nominal().start_positions();
  const Eigen::VectorXd difference =
      with.nominal().calc_mass_matrix(q).diagonal() - without.nominal().calc_mass_matrix(q).diagonal();
  const double omega = config.control.bandwidth;
  for (int j = 0; j < difference.size(); ++j) {
    const double armature = model.joints[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(j)])].armature;
    EXPECT_NEAR(difference[j], armature, 1e-9) << "joint " << j + 1;
    // The default gains follow the diagonal: kp differs by armature·ω².
    EXPECT_NEAR(with.gains().kp[j] - without.gains().kp[j], armature * omega * omega, 1e-6) << "joint " << j + 1;
  }
  std::printf("armature share of M_jj at the start posture, joints 1-7:");
  const Eigen::VectorXd full = with.nominal().calc_mass_matrix(q).diagonal();
  for (int j = 0; j < difference.size(); ++j) std::printf(" %.2f", difference[j] / full[j]);
  std::printf("\n");
}

}  // namespace
}  // namespace armfarm
