// URDF loading: every value of a small arm with known numbers, and the shipped models.
#include "engine/model/arm_reach.hpp"
#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {
namespace {

TEST(UrdfLoading, ReadsEveryValueOfASmallArm) {
  const ArmModel model = load_arm_model(test::data_path("rotated_inertia.urdf"));
  EXPECT_EQ(model.name, "rotated_inertia");
  ASSERT_EQ(model.links.size(), 5u);
  ASSERT_EQ(model.joints.size(), 4u);
  EXPECT_EQ(model.links[model.root_link].name, "base");
  EXPECT_TRUE(model.links[model.root_link].fixed_to_world);
  EXPECT_EQ(model.movable_joints(), (std::vector<int>{0, 1, 2}));

  // Inertia given about the COM in a frame rotated by rpy (fixed axes: R = Rz(y) Ry(p) Rx(r)).
  const Link& arm = model.links[model.find_link("arm")];
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())).toRotationMatrix();
  Eigen::Matrix3d given;
  given << 0.04, 0.001, -0.002, 0.001, 0.05, 0.003, -0.002, 0.003, 0.02;
  EXPECT_DOUBLE_EQ(arm.inertial.mass, 2.5);
  EXPECT_LT((arm.inertial.com - Eigen::Vector3d(0.01, 0.02, 0.25)).norm(), 1e-15);
  EXPECT_LT((arm.inertial.inertia - rotation * given * rotation.transpose()).norm(), 1e-12);
  EXPECT_NEAR(arm.inertial.inertia.trace(), given.trace(), 1e-12);  // invariant under rotation

  const Joint& turn = model.joints[model.find_joint("turn")];
  EXPECT_EQ(turn.type, JointType::revolute);
  EXPECT_LT((turn.axis - Eigen::Vector3d::UnitZ()).norm(), 1e-15);  // (0 0 2) normalised
  EXPECT_LT((turn.origin.translation() - Eigen::Vector3d(0.1, 0.2, 0.3)).norm(), 1e-15);
  EXPECT_LT((turn.origin.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_TRUE(turn.has_position_limits);
  EXPECT_DOUBLE_EQ(turn.lower, -1.5);
  EXPECT_DOUBLE_EQ(turn.upper, 2.5);
  EXPECT_DOUBLE_EQ(turn.effort_limit, 40.0);
  EXPECT_DOUBLE_EQ(turn.velocity_limit, 3.0);
  EXPECT_DOUBLE_EQ(turn.damping, 0.7);
  EXPECT_DOUBLE_EQ(turn.friction, 0.3);
  EXPECT_NEAR(turn.armature, 2e-5 * 100 * 100, 1e-15);  // rotorInertia · reduction²
  EXPECT_DOUBLE_EQ(turn.start_position, 0.25);

  const Joint& slide = model.joints[model.find_joint("slide")];
  EXPECT_EQ(slide.type, JointType::prismatic);
  EXPECT_DOUBLE_EQ(slide.lower, -0.1);
  EXPECT_DOUBLE_EQ(slide.start_position, 0.05);
  EXPECT_DOUBLE_EQ(slide.armature, 0.0);

  const Joint& spin = model.joints[model.find_joint("spin")];
  EXPECT_EQ(spin.type, JointType::continuous);
  EXPECT_FALSE(spin.has_position_limits);
  EXPECT_EQ(spin.effort_limit, std::numeric_limits<double>::infinity());
  EXPECT_EQ(spin.velocity_limit, std::numeric_limits<double>::infinity());

  EXPECT_EQ(model.joints[model.find_joint("tool_mount")].type, JointType::fixed);
  // Default end effector: the single leaf link, offset zero.
  EXPECT_EQ(model.links[model.end_effector.link].name, "tool");
  EXPECT_EQ(model.end_effector.offset, Eigen::Vector3d::Zero());
  EXPECT_NEAR(model.total_mass(), 2.5 + 0.5 + 0.2, 1e-12);
}

TEST(UrdfLoading, LwrTotalMassReachAndDrives) {
  const ArmModel model = load_arm_model(test::models_path("dlr_lwr3.urdf"));
  EXPECT_EQ(model.movable_joints().size(), 7u);
  EXPECT_NEAR(model.total_mass(), 13.5, 0.5);  // DLR LWR III: about 13.5 kg
  EXPECT_NEAR(calc_reach(model), 1.0, 0.05);   // about 1 m from the first joint
  // Stretched straight up, the end effector sits at shoulder height plus the reach.
  const auto poses = calc_zero_configuration_link_poses(model);
  const Eigen::Vector3d tip = poses[model.end_effector.link] * model.end_effector.offset;
  EXPECT_LT((tip - Eigen::Vector3d(0, 0, 0.31 + calc_reach(model))).norm(), 1e-9);
  for (int j : model.movable_joints()) {
    const Joint& joint = model.joints[j];
    EXPECT_GT(joint.armature, 0.05) << joint.name;   // reflected rotor inertia O(0.1) kg·m²
    EXPECT_LT(joint.armature, 1.0) << joint.name;
    EXPECT_TRUE(std::isfinite(joint.effort_limit)) << joint.name;
    EXPECT_GE(joint.start_position, joint.lower) << joint.name;
  }
  EXPECT_DOUBLE_EQ(model.joints[model.find_joint("joint_1")].effort_limit, 176.0);
  EXPECT_DOUBLE_EQ(model.joints[model.find_joint("joint_7")].effort_limit, 30.0);
}

TEST(UrdfLoading, PlanarArmMatchesItsDocumentedNumbers) {
  const ArmModel model = load_arm_model(test::models_path("planar2.urdf"));
  ASSERT_EQ(model.movable_joints().size(), 2u);
  EXPECT_NEAR(model.total_mass(), 3.5, 1e-12);
  EXPECT_NEAR(calc_reach(model), 1.8, 1e-12);
  for (int j : model.movable_joints()) EXPECT_LT((model.joints[j].axis - Eigen::Vector3d::UnitY()).norm(), 1e-15);
  const Link& link_2 = model.links[model.find_link("link_2")];
  EXPECT_NEAR(link_2.inertial.inertia(1, 1), 1.5 * (3 * 0.02 * 0.02 + 0.64) / 12.0, 1e-9);
}

// A two-joint arm (lines 1-14), then `extensions` (from line 15) and </robot>.
std::string write_urdf(const std::string& joint_limits, const std::string& extensions) {
  const std::string inertial =
      "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>";
  const std::string path = test_support::scratch_file("steps.urdf");
  std::ofstream(path, std::ios::binary) << "<robot name=\"steps\" xmlns:armfarm=\"https://armfarm.invalid/urdf-extensions\">\n"
                                           "<link name=\"base\"/>\n"
                                           "<joint name=\"shoulder\" type=\"revolute\">\n"
                                           "  <parent link=\"base\"/><child link=\"upper\"/>\n"
                                           "  <axis xyz=\"0 0 1\"/>\n"
                                           "  " + joint_limits + "\n"
                                           "</joint>\n"
                                           "<link name=\"upper\">" + inertial + "</link>\n"
                                           "<joint name=\"wrist\" type=\"continuous\">\n"
                                           "  <parent link=\"upper\"/><child link=\"hand\"/>\n"
                                           "  <origin xyz=\"0 0 0.3\"/><axis xyz=\"0 1 0\"/>\n"
                                           "  <limit lower=\"-2\" upper=\"2\" effort=\"5\" velocity=\"0\"/>\n"
                                           "</joint>\n"
                                           "<link name=\"hand\">" + inertial + "</link>\n" +
                                               extensions + "</robot>\n";
  return path;
}

TEST(UrdfLoading, ZeroEffortOrVelocityIsNoLimitAndOnlyRevoluteOrPrismaticJointsKeepPositionLimits) {
  const std::string path = write_urdf("<limit lower=\"-1\" upper=\"1.5\" effort=\"0\" velocity=\"2\"/>", "");
  const ArmModel model = load_arm_model(path);
  std::remove(path.c_str());
  const Joint& shoulder = model.joints[model.find_joint("shoulder")];
  EXPECT_EQ(shoulder.type, JointType::revolute);
  EXPECT_EQ(shoulder.effort_limit, std::numeric_limits<double>::infinity());  // effort="0": none given
  EXPECT_DOUBLE_EQ(shoulder.velocity_limit, 2.0);
  EXPECT_TRUE(shoulder.has_position_limits);
  EXPECT_DOUBLE_EQ(shoulder.lower, -1.0);
  EXPECT_DOUBLE_EQ(shoulder.upper, 1.5);
  // A continuous joint's <limit> gives its effort (and velocity), never position limits.
  const Joint& wrist = model.joints[model.find_joint("wrist")];
  EXPECT_EQ(wrist.type, JointType::continuous);
  EXPECT_DOUBLE_EQ(wrist.effort_limit, 5.0);
  EXPECT_EQ(wrist.velocity_limit, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(wrist.has_position_limits);
  EXPECT_LT((wrist.origin.translation() - Eigen::Vector3d(0, 0, 0.3)).norm(), 1e-15);
}

TEST(UrdfLoading, ArmfarmExtensionsThatRepeatOrReferToNothingNameTheirLine) {
  const std::string limits = "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"2\"/>";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"<armfarm:end_effector link=\"hand\"/>\n<armfarm:end_effector link=\"upper\"/>\n", ":16: second <armfarm:end_effector>"},
      {"<armfarm:end_effector link=\"elbow\"/>\n", ":15: <armfarm:end_effector>: unknown link 'elbow'"},
      {"<armfarm:start_position joint=\"wrist\" value=\"0.1\"/>\n<armfarm:start_position joint=\"wrist\" value=\"0.2\"/>\n",
       ":16: second start position for joint 'wrist'"},
      {"<armfarm:start_position joint=\"elbow\" value=\"0.1\"/>\n", ":15: <armfarm:start_position>: unknown joint 'elbow'"},
  };
  for (const auto& [extensions, problem] : cases) {
    const std::string path = write_urdf(limits, extensions);
    EXPECT_EQ(test::load_error(path), path + problem) << extensions;
    std::remove(path.c_str());
  }
  // Given once, they are the joint's start and the end effector.
  const std::string path =
      write_urdf(limits, "<armfarm:start_position joint=\"wrist\" value=\"0.25\"/>\n"
                         "<armfarm:end_effector link=\"upper\" offset=\"0 0 0.1\"/>\n");
  const ArmModel model = load_arm_model(path);
  std::remove(path.c_str());
  EXPECT_DOUBLE_EQ(model.joints[model.find_joint("wrist")].start_position, 0.25);
  EXPECT_TRUE(model.joints[model.find_joint("wrist")].start_position_from_file);
  EXPECT_EQ(model.links[model.end_effector.link].name, "upper");
  EXPECT_EQ(model.end_effector.offset, Eigen::Vector3d(0, 0, 0.1));
}

}  // namespace
}  // namespace armfarm
