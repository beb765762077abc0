// Choosing the end effector: the single leaf by default, a named link (config or --ee) on a
// file with several leaves, the file's own element, and the errors that list the leaves. The
// URDF extension elements a ROS-style file carries: urdf_loading_test.cpp; the shared tree
// ordering: model_file_test.cpp.
#include "engine/model/end_effector.hpp"
#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

namespace armfarm {
namespace {

using test::load_error;

TEST(EndEffector, SeveralLeavesAreRefusedWithTheirNamesAndHowToChoose) {
  const std::string path = test::data_path("two_leaves.urdf");
  const std::string message = load_error(path, {});
  EXPECT_EQ(message, path + ": 2 leaf links ('tool0', 'camera_link'): set end_effector.link to the one that tracks the "
                            "targets (in a spec's base or as a grid axis; --ee LINK[:x,y,z] on armfarm job and the model commands)");
  const ArmModel structure = load_arm_model_file(path);  // the structure loads without a choice
  EXPECT_EQ(structure.end_effector.link, -1);
  EXPECT_EQ(structure.movable_joints().size(), 2u);
}

TEST(EndEffector, ANamedLinkAndOffsetAreTheEndEffector) {
  const std::string path = test::data_path("two_leaves.urdf");
  const ArmModel tool = load_arm_model(path, {"tool0", Eigen::Vector3d::Zero()});
  EXPECT_EQ(tool.links[tool.end_effector.link].name, "tool0");
  const ArmModel camera = load_arm_model(path, {"camera_link", Eigen::Vector3d(0, 0, 0.02)});
  EXPECT_EQ(camera.links[camera.end_effector.link].name, "camera_link");
  EXPECT_EQ(camera.end_effector.offset, Eigen::Vector3d(0, 0, 0.02));
  // Any link may be chosen, not only a leaf: the tip of the forearm itself.
  const ArmModel fore = load_arm_model(path, {"fore", Eigen::Vector3d(0.4, 0, 0)});
  const test::ForwardKinematics fk = test::calc_forward_kinematics(fore, {0.3, -0.5});
  const Eigen::Vector3d via_fore = fk.links[fore.end_effector.link] * fore.end_effector.offset;
  const Eigen::Vector3d via_tool = fk.links[tool.find_link("tool0")].translation();
  EXPECT_LT((via_fore - via_tool).norm(), 1e-12);
}

TEST(EndEffector, AnUnknownLinkListsTheLeaves) {
  const std::string path = test::data_path("two_leaves.urdf");
  EXPECT_EQ(load_error(path, {"tool", Eigen::Vector3d::Zero()}),
            path + ": end_effector.link: no link 'tool' (leaf links: 'tool0', 'camera_link')");
  EXPECT_NE(load_error(path, {"", Eigen::Vector3d(0, 0, 1)}).find("an offset needs end_effector.link"), std::string::npos);
}

TEST(EndEffector, TheFilesElementIsTheDefaultAndAChoiceOverridesIt) {
  const std::string path = test::models_path("planar2.urdf");  // <armfarm:end_effector link="link_2" offset="0.8 0 0"/>
  const ArmModel own = load_arm_model(path);
  EXPECT_EQ(own.links[own.end_effector.link].name, "link_2");
  EXPECT_EQ(own.end_effector.offset, Eigen::Vector3d(0.8, 0, 0));
  const ArmModel chosen = load_arm_model(path, {"link_1", Eigen::Vector3d(1.0, 0, 0)});
  EXPECT_EQ(chosen.links[chosen.end_effector.link].name, "link_1");
  EXPECT_EQ(chosen.end_effector.offset, Eigen::Vector3d(1.0, 0, 0));
}

TEST(EndEffector, DcgWithSeveralLeavesAsksToo) {
  const auto folder = std::filesystem::temp_directory_path() / ("armfarm_ee_dcg_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "fork.dcg").string();
  std::ofstream(path) << "<DCGraph>\n"
                         "B base <t(0 0 0)> o(1) s(0.1 0.1 0.1) fix ;\n"
                         "B left <> o(1) s(0.1 0.1 0.4) w(1) ;\n"
                         "B right <> o(1) s(0.1 0.1 0.4) w(1) ;\n"
                         "J base-left <t(0 0 0.1) || t(0 0 0.2)> ;\n"
                         "J base-right <t(0 0 0.1) || t(0 0 0.2)> ;\n"
                         "</DCGraph>\n";
  EXPECT_NE(load_error(path, {}).find("2 leaf links ('left', 'right')"), std::string::npos) << load_error(path, {});
  const ArmModel right = load_arm_model(path, {"right", Eigen::Vector3d(0, 0, 0.2)});
  EXPECT_EQ(right.links[right.end_effector.link].name, "right");
  std::filesystem::remove_all(folder);
}

TEST(EndEffector, CommandLineText) {
  EXPECT_EQ(parse_end_effector_text("tool0").link, "tool0");
  EXPECT_EQ(parse_end_effector_text("tool0").offset, Eigen::Vector3d::Zero());
  const EndEffectorConfig tip = parse_end_effector_text("link_7:0,0,0.126");
  EXPECT_EQ(tip.link, "link_7");
  EXPECT_EQ(tip.offset, Eigen::Vector3d(0, 0, 0.126));
  EXPECT_EQ(parse_end_effector_text("a:-1e-2,2,3").offset, Eigen::Vector3d(-0.01, 2, 3));
  for (const char* bad : {"", ":1,2,3", "tool0:", "tool0:1,2", "tool0:1,2,3,4", "tool0:1,x,3", "tool0:1,,3", "tool0:nan,0,0"}) {
    EXPECT_THROW(parse_end_effector_text(bad), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace armfarm

namespace armfarm {
namespace {

// An arm of one joint whose link carries `frames` fixed frames: that many leaves.
ArmModel make_many_leaves(int frames) {
  ArmModel model;
  model.name = "many_leaves";
  model.source_file = "many.urdf";
  model.links.resize(2);
  model.links[0].name = "base";
  model.links[0].fixed_to_world = true;
  model.links[1].name = "arm";
  model.links[1].inertial.mass = 1.0;
  model.links[1].inertial.inertia = Eigen::Matrix3d::Identity() * 0.01;
  Joint pivot;
  pivot.name = "pivot";
  pivot.parent_link = 0;
  pivot.child_link = 1;
  model.joints.push_back(pivot);
  for (int i = 0; i < frames; ++i) {
    Link frame;
    frame.name = "frame_" + std::to_string(i + 1);
    model.links.push_back(frame);
    Joint weld;
    weld.name = "weld_" + std::to_string(i + 1);
    weld.type = JointType::fixed;
    weld.parent_link = 1;
    weld.child_link = static_cast<int>(model.links.size()) - 1;
    model.joints.push_back(weld);
  }
  return model;
}

std::string choose_error(ArmModel model, const EndEffectorConfig& choice) {
  try {
    choose_end_effector(model, choice);
  } catch (const ModelError& error) {
    return error.what();
  }
  return "";
}

TEST(EndEffector, LongLeafListsAreCappedInOneLine) {
  const std::string message = choose_error(make_many_leaves(25), {});
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_NE(message.find("25 leaf links ('frame_1', 'frame_2'"), std::string::npos) << message;
  EXPECT_NE(message.find("'frame_10' … and 15 more): set end_effector.link"), std::string::npos) << message;
  EXPECT_EQ(message.find("frame_11"), std::string::npos) << message;
  const std::string unknown = choose_error(make_many_leaves(11), {"nowhere", Eigen::Vector3d::Zero()});
  EXPECT_NE(unknown.find("many.urdf: end_effector.link: no link 'nowhere' (leaf links: 'frame_1'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("'frame_10' … and 1 more)"), std::string::npos) << unknown;
  // Exactly ten: all listed, nothing "more".
  EXPECT_EQ(choose_error(make_many_leaves(10), {}).find("more"), std::string::npos);
}

}  // namespace
}  // namespace armfarm
