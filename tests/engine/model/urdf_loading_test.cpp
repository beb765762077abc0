// URDF loading: every value of a small arm with known numbers, and the shipped models; the
// extension elements a ROS-style file carries, namespaced elements skipped, vendor habits.
#include "engine/model/arm_reach.hpp"
#include "engine/model/end_effector.hpp"
#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

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

using test::load_error;

TEST(UrdfExtensions, RosStyleSevenDofFileLoadsWithItsExtensionElements) {
  // gazebo, transmission with hardware interfaces and drake:rotor_inertia / drake:gear_ratio,
  // ros2_control, drake:* at the top level and inside <collision>, visual/collision meshes as
  // package:// URIs (never opened).
  const std::string path = test::data_path("ros7_arm.urdf");
  const ArmModel model = load_arm_model(path, {"ee", Eigen::Vector3d::Zero()});
  EXPECT_EQ(model.movable_joints().size(), 7u);
  EXPECT_EQ(model.input_files, std::vector<std::string>{path});  // no mesh is read
  EXPECT_NEAR(model.total_mass(), 5.0 + 4.0 + 4.0 + 3.0 + 2.7 + 1.7 + 1.8 + 0.3, 1e-12);
  // Armature from Drake's transmission elements: rotor inertia × gear ratio².
  const std::vector<int> movable = model.movable_joints();
  for (int n = 0; n < 7; ++n) {
    EXPECT_NEAR(model.joints[movable[n]].armature, (n < 4 ? 1e-5 : 4e-6) * 160.0 * 160.0, 1e-12) << n;
  }
  // Straight up at zero: the ee frame 0.1575 + 0.2025 + 0.2045 + 0.2155 + 0.1845 + 0.2155 + 0.081 + 0.171 m above the base.
  const test::ForwardKinematics fk = test::calc_forward_kinematics(model, std::vector<double>(7, 0.0));
  EXPECT_LT((fk.links[model.end_effector.link].translation() - Eigen::Vector3d(0, 0, 1.432)).norm(), 1e-12);
  EXPECT_NE(load_error(path, {}).find("3 leaf links ('flange', 'tool0', 'ee')"), std::string::npos);
  // The vendor-style <self_collision_checking> is skipped with a warning; strict reading refuses it.
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_EQ(model.warnings[0], path + ":51: <self_collision_checking> in <link> of link 'base_link' is not a URDF element");
  try {
    check_strict_model(model);
    ADD_FAILURE() << "strict reading accepted <self_collision_checking>";
  } catch (const ModelError& error) {
    EXPECT_EQ(std::string(error.what()), model.warnings[0] + " (refused under --strict)");
  }
  EXPECT_NO_THROW(check_strict_model(load_arm_model(test::models_path("dlr_lwr3.urdf"))));
}

TEST(UrdfExtensions, NamespacedElementsInsideLinksAndJointsAreSkipped) {
  const auto folder = std::filesystem::temp_directory_path() / ("armfarm_ee_ext_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "ext.urdf").string();
  std::ofstream(path) << R"(<robot name="ext" xmlns:drake="http://drake.mit.edu">
  <link name="base"/>
  <frame name="tcp" link="tip" xyz="0 0 0.1"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>
    <drake:acceleration lower="-10" upper="10"/></joint>
  <link name="tip"><drake:compliant_hydroelastic/>
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <sensor name="cam"/>
</robot>
)";
  const ArmModel model = load_arm_model(path);
  EXPECT_EQ(model.links[model.end_effector.link].name, "tip");
  std::filesystem::remove_all(folder);
}

TEST(UrdfExtensions, VendorHabitsBaseFramesAndAxislessFixedJointsLoad) {
  // Kinova's and Jaco's files write <axis xyz="0 0 0"/> on fixed joints; Drake's UR files weld a
  // 'base' frame to the base link. Neither frame moves, so it is not a leaf: the tip is chosen.
  const auto folder = std::filesystem::temp_directory_path() / ("armfarm_ee_vendor_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "vendor.urdf").string();
  std::ofstream(path) << R"(<robot name="vendor">
  <link name="world"/>
  <joint name="mount" type="fixed"><parent link="world"/><child link="base_link"/><axis xyz="0 0 0"/></joint>
  <link name="base_link"><inertial><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="base_frame" type="fixed"><parent link="base_link"/><child link="base"/><axis xyz="0 0 0"/></joint>
  <link name="base"/>
  <joint name="j" type="continuous"><parent link="base_link"/><child link="tip"/><axis xyz="0 0 1"/></joint>
  <link name="tip"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="flange" type="fixed"><parent link="tip"/><child link="tool0"/><origin xyz="0 0 0.1"/><axis xyz="0 0 0"/></joint>
  <link name="tool0"/>
</robot>
)";
  const ArmModel model = load_arm_model(path);
  const std::vector<int> leaves = find_leaf_links(model);
  ASSERT_EQ(leaves.size(), 1u);
  EXPECT_EQ(model.links[leaves[0]].name, "tool0");
  EXPECT_EQ(model.links[model.end_effector.link].name, "tool0");
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
