// The default start posture: 0 clamped into the middle half of each joint's range, and the
// loaders' use of it (a file's own start positions kept and marked as the file's).
#include "engine/model/start_posture.hpp"
#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

Joint make_joint(double lower, double upper, JointType type = JointType::revolute) {
  Joint joint;
  joint.type = type;
  joint.has_position_limits = type == JointType::revolute || type == JointType::prismatic;
  joint.lower = lower;
  joint.upper = upper;
  return joint;
}

TEST(StartPosture, ZeroIsKeptWhereAQuarterOfTheRangeIsFreeOnEitherSide) {
  EXPECT_EQ(calc_default_start_position(make_joint(-2.0, 2.0)), 0.0);
  EXPECT_EQ(calc_default_start_position(make_joint(-1.0, 3.0)), 0.0);   // exactly a quarter below: kept
  EXPECT_EQ(calc_default_start_position(make_joint(-1.5, 1.4)), 0.0);   // OpenManipulator-X joint 3
  EXPECT_EQ(calc_default_start_position(make_joint(0, 0, JointType::continuous)), 0.0);
  EXPECT_EQ(calc_default_start_position(make_joint(0, 0, JointType::fixed)), 0.0);
}

TEST(StartPosture, ARangeThatExcludesZeroStartsAQuarterInFromTheNearerEnd) {
  // The Panda's joint 4: [-3.0718, -0.0698], range 3.002, a quarter 0.7505.
  EXPECT_NEAR(calc_default_start_position(make_joint(-3.0718, -0.0698)), -0.0698 - 0.7505, 1e-12);
  // Its joint 6: 0 lies inside [-0.0175, 3.7525] but 0.0175 from its end.
  EXPECT_NEAR(calc_default_start_position(make_joint(-0.0175, 3.7525)), -0.0175 + 0.9425, 1e-12);
  EXPECT_NEAR(calc_default_start_position(make_joint(0.2, 0.6, JointType::prismatic)), 0.3, 1e-15);
  EXPECT_EQ(calc_default_start_position(make_joint(0.5, 0.5)), 0.5);  // a range of one point
}

TEST(StartPosture, LoadersKeepTheFilesPostureAndDefaultTheRest) {
  const ArmModel lwr = load_arm_model_file(test::models_path("dlr_lwr3.urdf"));
  const std::vector<int> movable = lwr.movable_joints();
  const double expected[] = {0.0, -M_PI / 4, M_PI / 2, M_PI / 2, 0.0, 0.0, 0.0};  // appendix C (written to 10 digits); the rest 0
  const bool from_file[] = {false, true, true, true, false, false, false};
  for (std::size_t j = 0; j < movable.size(); ++j) {
    EXPECT_NEAR(lwr.joints[movable[j]].start_position, expected[j], 1e-9) << "joint " << j + 1;
    EXPECT_EQ(lwr.joints[movable[j]].start_position_from_file, from_file[j]) << "joint " << j + 1;
  }
  const ArmModel dcg = load_arm_model_file(test::models_path("dlr_lwr3.dcg"));
  for (std::size_t j = 0; j < movable.size(); ++j) {
    EXPECT_NEAR(dcg.joints[dcg.movable_joints()[j]].start_position, expected[j], 1e-9) << "joint " << j + 1;
  }
  // A file whose zero posture is outside a joint's range loads, starting inside it.
  const ArmModel panda = load_arm_model_file(std::string(ARMFARM_TEST_DATA_DIR) + "/arms/franka_panda.urdf");
  for (int index : panda.movable_joints()) {
    const Joint& joint = panda.joints[index];
    EXPECT_FALSE(joint.start_position_from_file);
    EXPECT_GE(joint.start_position, joint.lower) << joint.name;
    EXPECT_LE(joint.start_position, joint.upper) << joint.name;
  }
  EXPECT_NEAR(panda.joints[panda.movable_joints()[3]].start_position, -0.8203, 1e-12);
}

}  // namespace
}  // namespace armfarm
