// `armfarm model info`: the shipped models and the arm corpus print their summary and exit 0
// (an arm whose zero posture is outside a joint's range too, with a start posture inside the
// limits); per joint the default job's mass-matrix diagonal and gains; a bad file exits 2 with
// the loader's one-line message.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
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

const std::string kArms = std::string(ARMFARM_TEST_DATA_DIR) + "/arms/";

nlohmann::json read_info(const std::string& arguments) {
  const CommandResult result = run_armfarm("model info --json " + arguments);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return nlohmann::json::parse(result.output.substr(std::min(result.output.find('{'), result.output.size())));
}

TEST(CmdModelInfo, EveryCorpusArmLoadsAndPrints) {
  for (const char* file : {"ur5e.urdf", "kuka_iiwa14.urdf", "franka_panda.urdf", "kinova_gen3.urdf", "open_manipulator_x.urdf"}) {
    const CommandResult result = run_armfarm("model info " + kArms + file);
    EXPECT_EQ(result.exit_code, 0) << file << ": " << result.output;
    EXPECT_NE(result.output.find("the default job on each joint"), std::string::npos) << result.output;
  }
}

TEST(CmdModelInfo, AnArmWhoseRangeExcludesZeroShowsAStartPostureInsideTheLimits) {
  const std::string panda = kArms + "franka_panda.urdf";
  const CommandResult text = run_armfarm("model info " + panda);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("\n  4  panda_joint4  revolute"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("-0.8203 (default)\n"), std::string::npos) << text.output;
  const nlohmann::json info = read_info(panda);
  int movable = 0;
  for (const nlohmann::json& joint : info.at("joints")) {
    if (joint.at("number").is_null()) continue;
    ++movable;
    const double start = joint.at("start_position").get<double>();
    EXPECT_GE(start, joint.at("lower").get<double>()) << joint.at("name");
    EXPECT_LE(start, joint.at("upper").get<double>()) << joint.at("name");
    EXPECT_FALSE(joint.at("start_position_from_file").get<bool>());
    EXPECT_GT(joint.at("default_job").at("mass_diagonal").get<double>(), 0.0) << joint.at("name");
  }
  EXPECT_EQ(movable, 7);
  EXPECT_NEAR(info.at("joints").at(4).at("start_position").get<double>(), -0.0698 - 0.25 * 3.002, 1e-12);  // joint 4
  EXPECT_EQ(info.at("end_effector").at("link"), "panda_link8");
}

TEST(CmdModelInfo, DefaultJobFiguresFollowTheClosedFormOfThePlanarArm) {
  // planar2 at its start posture (0, 0): both links along x. Slender rods of models/planar2.urdf:
  // M11 = m1 c1² + I1 + m2 (L1² + c2² + 2 L1 c2) + I2, M22 = m2 c2² + I2 (I about the COM, y axis).
  const double m1 = 2.0, c1 = 0.5, i1 = 0.1668666667, m2 = 1.5, l1 = 1.0, c2 = 0.4, i2 = 0.08015;
  const double diagonal[] = {m1 * c1 * c1 + i1 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2) + i2, m2 * c2 * c2 + i2};
  const nlohmann::json info = read_info(kModels + "planar2.urdf");
  for (int j = 0; j < 2; ++j) {
    const nlohmann::json& figures = info.at("joints").at(j).at("default_job");
    const double m = figures.at("mass_diagonal").get<double>();
    EXPECT_NEAR(m, diagonal[j], 1e-9) << "joint " << j + 1;
    // The default gains: 20 rad/s, critically damped, gain scale 1 (control_config.hpp).
    EXPECT_NEAR(figures.at("kp").get<double>(), m * 400.0, 1e-9 * m * 400.0);
    EXPECT_NEAR(figures.at("kd").get<double>(), m * 40.0, 1e-9 * m * 40.0);
  }
}

// The steps "auto" picks for planar2's default job against the coupled closed form: with gains
// placed on the diagonal (kd = 40·M_jj), the fastest mode of M⁻¹Kd has kd·h/M = 40·h / (1 − r),
// r = M12 / √(M11·M22) (det(D − λM) = 0 for D = diag M). At one PD period (h = 10 ms; the
// criterion asks for stability at 1.5 × h) that is 0.6 / (1 − r) = 3.9, above the bound 2; at two
// (h = 5 ms, 1.5 × h: 1.96) below it: "auto" picks pd_substeps 2, and the ratio printed is 0.2 / (1 − r).
TEST(CmdModelInfo, AutoStepsFollowTheCoupledClosedFormOfThePlanarArm) {
  const double m1 = 2.0, c1 = 0.5, i1 = 0.1668666667, m2 = 1.5, l1 = 1.0, c2 = 0.4, i2 = 0.08015;
  const double m11 = m1 * c1 * c1 + i1 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2) + i2, m22 = m2 * c2 * c2 + i2;
  const double m12 = m2 * (c2 * c2 + l1 * c2) + i2;
  const double r = m12 / std::sqrt(m11 * m22);
  ASSERT_GT(0.6 / (1.0 - r), 2.0);
  ASSERT_LT(0.3 / (1.0 - r), 2.0);
  const nlohmann::json info = read_info(kModels + "planar2.urdf");
  const nlohmann::json& steps = info.at("default_job_steps");
  EXPECT_EQ(steps.at("dt"), 0.01);
  EXPECT_EQ(steps.at("pd_substeps"), 2);
  EXPECT_EQ(steps.at("integrator_steps_per_tick"), 1);  // no damping: RK4's passive bound is not in play
  EXPECT_EQ(steps.at("stable"), true);
  EXPECT_EQ(steps.at("over_trajectories"), true);
  EXPECT_NEAR(steps.at("modal_kd_h_over_m").get<double>(), 0.2 / (1.0 - r), 1e-9);
  EXPECT_LE(steps.at("spectral_radius").get<double>(), 1.0);
  for (int j = 0; j < 2; ++j) {  // one joint alone: kd·h/M = 2ζω·h = 0.2, kp·h²/M = ω²h² = 0.01
    EXPECT_NEAR(info.at("joints").at(j).at("default_job").at("kd_h_over_m").get<double>(), 0.2, 1e-12);
    EXPECT_NEAR(info.at("joints").at(j).at("default_job").at("kp_h2_over_m").get<double>(), 0.01, 1e-12);
  }
  const CommandResult text = run_armfarm("model info " + kModels + "planar2.urdf");
  EXPECT_NE(text.output.find("steps (\"auto\"): dt 0.01 s, pd_substeps 2 (PD period h = 0.005 s), integrator_steps_per_tick 1"),
            std::string::npos)
      << text.output;
  // The LWR III keeps the thesis's single 10 ms loop; the armature-free iiwa without an end
  // effector is judged at its start posture only, and says so.
  EXPECT_EQ(read_info(kModels + "dlr_lwr3.urdf").at("default_job_steps").at("pd_substeps"), 1);
  const nlohmann::json iiwa = read_info(kArms + "kuka_iiwa14.urdf").at("default_job_steps");
  EXPECT_EQ(iiwa.at("over_trajectories"), false);
  EXPECT_EQ(iiwa.at("trajectory_problem"), "no end effector chosen");
  EXPECT_GT(iiwa.at("pd_substeps").get<int>(), 1);
}

TEST(CmdModelInfo, TwoLeavesShowBothAndTheChoiceWithEe) {
  const nlohmann::json open = read_info(kArms + "kuka_iiwa14.urdf");
  EXPECT_EQ(open.at("leaf_links"), nlohmann::json::array({"iiwa_link_ee", "tool_tcp"}));
  EXPECT_TRUE(open.at("end_effector").is_null());
  EXPECT_NE(open.at("end_effector_problem").get<std::string>().find("set end_effector.link"), std::string::npos);
  EXPECT_GT(open.at("joints").at(7).at("default_job").at("mass_diagonal").get<double>(), 0.0);  // joint 7: figures without a choice
  const nlohmann::json chosen = read_info("--ee tool_tcp " + kArms + "kuka_iiwa14.urdf");
  EXPECT_EQ(chosen.at("end_effector").at("link"), "tool_tcp");
  const CommandResult wrong = run_armfarm("model info --ee flange " + kArms + "kuka_iiwa14.urdf");
  EXPECT_EQ(wrong.exit_code, 2) << wrong.output;
  EXPECT_NE(wrong.output.find("no link 'flange' (leaf links: 'iiwa_link_ee', 'tool_tcp')"), std::string::npos) << wrong.output;
}

}  // namespace
