// `armfarm model info`: the shipped models print their summary and exit 0; a bad file exits 2
// with the loader's one-line message.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

const std::string kModels = std::string(ARMFARM_SOURCE_DIR) + "/models/";

TEST(CmdModelInfo, ShippedModelsShowTotalMass) {
  for (const char* file : {"dlr_lwr3.urdf", "dlr_lwr3.dcg", "planar2.urdf"}) {
    const CommandResult result = run_armfarm("model info " + kModels + file);
    EXPECT_EQ(result.exit_code, 0) << file << ": " << result.output;
    EXPECT_NE(result.output.find("total mass: "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("reach: "), std::string::npos) << result.output;
  }
  const CommandResult planar = run_armfarm("model info " + kModels + "planar2.urdf");
  EXPECT_NE(planar.output.find("total mass: 3.5000 kg"), std::string::npos) << planar.output;
}

TEST(CmdModelInfo, JsonHasStableKeys) {
  const CommandResult result = run_armfarm("model info --json " + kModels + "dlr_lwr3.urdf");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json info = nlohmann::json::parse(result.output);
  EXPECT_EQ(info.at("degrees_of_freedom"), 7);
  EXPECT_NEAR(info.at("total_mass").get<double>(), 13.5, 0.5);
  EXPECT_NEAR(info.at("reach").get<double>(), 1.0, 0.05);
  EXPECT_EQ(info.at("end_effector").at("link"), "link_7");
  const nlohmann::json& joint = info.at("joints").at(1);
  EXPECT_EQ(joint.at("name"), "joint_1");
  EXPECT_EQ(joint.at("number"), 1);  // 1-based, as active_joints
  EXPECT_EQ(info.at("joints").at(7).at("number"), 7);
  EXPECT_EQ(info.at("joints").at(0).at("number"), nullptr);  // the fixed mount
  EXPECT_EQ(joint.at("type"), "revolute");
  for (const char* key : {"axis", "lower", "upper", "effort_limit", "velocity_limit", "armature", "damping", "friction",
                          "start_position", "parent", "child"}) {
    EXPECT_TRUE(joint.contains(key)) << key;
  }
}

TEST(CmdModelInfo, TextNumbersJointsFromOne) {
  const CommandResult result = run_armfarm("model info " + kModels + "dlr_lwr3.urdf");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("\n  1  joint_1 "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("\n  7  joint_7 "), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("\n  0  joint_"), std::string::npos) << result.output;
}

TEST(CmdModelInfo, SeveralLeavesShowWithoutAnEndEffectorUntilChosen) {
  const std::string path = std::string(ARMFARM_TEST_DATA_DIR) + "/models/ros7_arm.urdf";
  const CommandResult open = run_armfarm("model info --json " + path);
  ASSERT_EQ(open.exit_code, 0) << open.output;
  // The file's <self_collision_checking> gives one warning line on stderr before the JSON.
  EXPECT_EQ(open.output.rfind("armfarm: warning: " + path + ":51: <self_collision_checking> in <link> of link 'base_link'", 0), 0u)
      << open.output;
  const nlohmann::json info = nlohmann::json::parse(open.output.substr(open.output.find('{')));
  EXPECT_EQ(info.at("warnings").size(), 1u);
  EXPECT_EQ(info.at("leaf_links"), nlohmann::json::array({"flange", "tool0", "ee"}));
  EXPECT_TRUE(info.at("end_effector").is_null());
  const CommandResult chosen = run_armfarm("model info --json --ee tool0:0,0,0.1 " + path);
  ASSERT_EQ(chosen.exit_code, 0) << chosen.output;
  const nlohmann::json tool = nlohmann::json::parse(chosen.output.substr(chosen.output.find('{')));
  EXPECT_EQ(tool.at("end_effector").at("link"), "tool0");
  EXPECT_EQ(tool.at("end_effector").at("offset"), nlohmann::json::array({0.0, 0.0, 0.1}));
  const CommandResult strict = run_armfarm("model info --strict " + path);
  EXPECT_EQ(strict.exit_code, 2) << strict.output;
  EXPECT_NE(strict.output.find(":51: <self_collision_checking> in <link> of link 'base_link' is not a URDF element (refused under --strict)"),
            std::string::npos)
      << strict.output;
}

TEST(CmdModelInfo, BadFileExitsTwoWithOneLine) {
  const std::string bad = std::string(ARMFARM_TEST_DATA_DIR) + "/models/bad/zero_mass.urdf";
  const CommandResult result = run_armfarm("model info " + bad);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("zero_mass.urdf:4: link 'upper': zero mass"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
  EXPECT_EQ(run_armfarm("model info " + kModels + "no_such_file.urdf").exit_code, 2);
  EXPECT_EQ(run_armfarm("model").exit_code, 2);  // the group needs a subcommand
}

}  // namespace
