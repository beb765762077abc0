// `armfarm model dynamics`: on models/planar2.urdf the torques, end-effector position and
// Jacobian equal the closed-form two-link arm (distributed masses), for all joints and for a
// subset; bad state vectors exit 2 with one line.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <sys/wait.h>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

const std::string kPlanar = std::string(ARMFARM_SOURCE_DIR) + "/models/planar2.urdf";

// planar2.urdf's figures (its header comment): both joints about +y, links along +x at zero,
// gravity −9.81 m/s² along z. In the plane (u, v) = (x, −z) the joints turn counter-clockwise,
// so this is the textbook two-link arm with gravity along +v.
constexpr double kL1 = 1.0, kL2 = 0.8, kM1 = 2.0, kM2 = 1.5, kC1 = 0.5, kC2 = 0.4, kG = 9.81;
constexpr double kI1 = 0.1668666667, kI2 = 0.08015;  // about the COM, about y

std::array<double, 2> closed_form_tau(const std::array<double, 6>& s) {
  const double q1 = s[0], q2 = s[1], qd1 = s[2], qd2 = s[3], qdd1 = s[4], qdd2 = s[5];
  const double c2 = std::cos(q2), s2 = std::sin(q2);
  const double m11 = kI1 + kI2 + kM1 * kC1 * kC1 + kM2 * (kL1 * kL1 + kC2 * kC2 + 2 * kL1 * kC2 * c2);
  const double m12 = kI2 + kM2 * (kC2 * kC2 + kL1 * kC2 * c2);
  const double m22 = kI2 + kM2 * kC2 * kC2;
  const double h = kM2 * kL1 * kC2 * s2;
  // V = −g (m1 c1 sin q1 + m2 (L1 sin q1 + c2 sin(q1 + q2))): potential energy with v = −z.
  const double g1 = -kG * ((kM1 * kC1 + kM2 * kL1) * std::cos(q1) + kM2 * kC2 * std::cos(q1 + q2));
  const double g2 = -kG * kM2 * kC2 * std::cos(q1 + q2);
  return {m11 * qdd1 + m12 * qdd2 - h * (2 * qd1 * qd2 + qd2 * qd2) + g1, m12 * qdd1 + m22 * qdd2 + h * qd1 * qd1 + g2};
}

std::string list(double a, double b) { return std::to_string(a) + "," + std::to_string(b); }

TEST(CmdModelDynamics, PlanarArmMatchesTheClosedForm) {
  const std::array<std::array<double, 6>, 4> states = {{
      {0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
      {0.3, -0.5, 0.2, 0.1, 1.0, -1.0},
      {-1.2, 2.0, -1.5, 0.7, -0.3, 2.5},
      {2.5, -2.9, 3.0, -2.0, 0.0, 0.0},
  }};
  for (const auto& s : states) {
    const CommandResult result = run_armfarm("model dynamics " + kPlanar + " --q " + list(s[0], s[1]) + " --qd " + list(s[2], s[3]) +
                                             " --qdd " + list(s[4], s[5]) + " --json");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const nlohmann::json out = nlohmann::json::parse(result.output);
    // std::to_string keeps six decimals: the closed form uses exactly what was passed.
    std::array<double, 6> passed{};
    for (int i = 0; i < 2; ++i) {
      passed[i] = out["q"][i];
      passed[2 + i] = out["qd"][i];
      passed[4 + i] = out["qdd"][i];
    }
    const std::array<double, 2> tau = closed_form_tau(passed);
    ASSERT_EQ(out["tau"].size(), 2u);
    EXPECT_NEAR(out["tau"][0].get<double>(), tau[0], 1e-8) << result.output;
    EXPECT_NEAR(out["tau"][1].get<double>(), tau[1], 1e-8) << result.output;
    const double q1 = passed[0], q12 = passed[0] + passed[1];
    const double x = kL1 * std::cos(q1) + kL2 * std::cos(q12), z = -(kL1 * std::sin(q1) + kL2 * std::sin(q12));
    EXPECT_NEAR(out["ee"][0].get<double>(), x, 1e-12);
    EXPECT_NEAR(out["ee"][1].get<double>(), 0.0, 1e-12);
    EXPECT_NEAR(out["ee"][2].get<double>(), z, 1e-12);
    const double jacobian[3][2] = {{-kL1 * std::sin(q1) - kL2 * std::sin(q12), -kL2 * std::sin(q12)},
                                   {0.0, 0.0},
                                   {-kL1 * std::cos(q1) - kL2 * std::cos(q12), -kL2 * std::cos(q12)}};
    ASSERT_EQ(out["jacobian"].size(), 3u);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 2; ++c) EXPECT_NEAR(out["jacobian"][r][c].get<double>(), jacobian[r][c], 1e-12) << r << "," << c;
    }
    EXPECT_EQ(out["active_joints"], nlohmann::json::array({1, 2}));
  }
}

TEST(CmdModelDynamics, ActiveSubsetLocksTheOthersAtTheirStart) {
  // Joint 2 alone, joint 1 locked at its start (0): the second link swings about x = 1 m.
  const CommandResult result = run_armfarm("model dynamics " + kPlanar + " --active 2 --q 0.7 --qdd 2 --json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json out = nlohmann::json::parse(result.output);
  const std::array<double, 2> tau = closed_form_tau({0.0, 0.7, 0.0, 0.0, 0.0, 2.0});
  ASSERT_EQ(out["tau"].size(), 1u);
  EXPECT_NEAR(out["tau"][0].get<double>(), tau[1], 1e-8);
  EXPECT_NEAR(out["jacobian"][2][0].get<double>(), -kL2 * std::cos(0.7), 1e-12);
  EXPECT_EQ(out["active_joints"], nlohmann::json::array({2}));
}

TEST(CmdModelDynamics, TextOutputNumbersJointsFromOne) {
  const CommandResult result = run_armfarm("model dynamics " + kPlanar + " --q 0,0");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("joint                              1             2"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("end effector (m, world): 1.8 0 0"), std::string::npos) << result.output;
}

TEST(CmdModelDynamics, BadStatesExitTwoWithOneLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"--q 0.1", "--q: 1 values for 2 active joints"},
      {"--q 0,0 --qd 1,2,3", "--qd: 3 values for 2 active joints"},
      {"--q 0 --active 3", "--active: joint 3 does not exist; " + kPlanar + " has joints 1..2"},
      {"--q 0,0 --active 1,1", "--active: joint 1 is listed twice"},
      {"--q 0,0 --ee link_3", "end_effector.link: no link 'link_3'"},
  };
  for (const auto& [arguments, expected] : cases) {
    const CommandResult result = run_armfarm("model dynamics " + kPlanar + " " + arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(expected), std::string::npos) << arguments << "\n" << result.output;
    EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
  }
}

}  // namespace
