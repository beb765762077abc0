// The serial chain's forward kinematics and Jacobian against Simbody's (ArmDynamics) at random
// states, for every link of the shipped models, with all joints and with active subsets (in
// any order, locked joints at non-zero start angles), and its Jacobian against central finite
// differences of its own forward kinematics.
#include "engine/kinematics/serial_chain.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {
namespace {

ArmModel load_shipped(const std::string& file) { return load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/" + file); }

/// Random angles within ±2 rad (±0.3 m for prismatic joints) for the chain's active joints.
Eigen::VectorXd draw_state(RandomStream& draws, const ArmModel& model, const std::vector<int>& active) {
  Eigen::VectorXd q(active.size());
  for (std::size_t c = 0; c < active.size(); ++c) {
    const double range = model.joints[active[c]].type == JointType::prismatic ? 0.3 : 2.0;
    q[c] = draws.uniform(-range, range);
  }
  return q;
}

/// Compares chain and Simbody for every link that moves, 20 random states and offsets each.
void expect_matches_simbody(const ArmModel& model, const std::vector<int>& movable_subset, const std::string& what) {
  ArmDynamics dynamics(model, movable_subset);
  const std::vector<int>& active = dynamics.active_joint_indices();
  RandomStream draws(11, "serial_chain_test." + what);
  int compared = 0;
  for (int link = 0; link < static_cast<int>(model.links.size()); ++link) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Vector3d offset(draws.uniform(-0.3, 0.3), draws.uniform(-0.3, 0.3), draws.uniform(-0.3, 0.3));
      const SerialChain chain(model, active, link, offset);
      ASSERT_EQ(chain.dof(), dynamics.dof());
      const Eigen::VectorXd q = draw_state(draws, model, active);
      Eigen::Vector3d position;
      Eigen::Matrix3Xd jacobian;
      chain.calc_position_and_jacobian(q, position, jacobian);
      const Eigen::Vector3d expected_position = dynamics.calc_point_position(q, link, offset);
      const Eigen::Matrix3Xd expected_jacobian = dynamics.calc_point_jacobian(q, link, offset);
      EXPECT_LT((position - expected_position).cwiseAbs().maxCoeff(), 1e-12) << what << " link " << link << " trial " << trial;
      EXPECT_LT((chain.calc_position(q) - expected_position).cwiseAbs().maxCoeff(), 1e-12) << what << " link " << link;
      ASSERT_EQ(jacobian.cols(), expected_jacobian.cols());
      EXPECT_LT((jacobian - expected_jacobian).cwiseAbs().maxCoeff(), 1e-12)
          << what << " link " << link << " trial " << trial << "\nchain\n" << jacobian << "\nsimbody\n" << expected_jacobian;
      ++compared;
    }
  }
  EXPECT_GT(compared, 0);
}

/// The shipped model with its joints' start angles set to random values, so locked joints sit
/// away from zero.
ArmModel with_random_start_angles(ArmModel model, std::uint64_t seed) {
  RandomStream draws(seed, "serial_chain_test.start_angles");
  for (Joint& joint : model.joints) {
    if (joint.type != JointType::fixed) joint.start_position = draws.uniform(-1.0, 1.0);
  }
  return model;
}

TEST(SerialChain, MatchesSimbodyOnTheLwr3Urdf) {
  const ArmModel model = with_random_start_angles(load_shipped("dlr_lwr3.urdf"), 1);
  expect_matches_simbody(model, {}, "urdf all");
  expect_matches_simbody(model, {0, 1, 3}, "urdf 1,2,4");
  expect_matches_simbody(model, {5, 2, 0}, "urdf 6,3,1");
  expect_matches_simbody(model, {6}, "urdf 7");
}

TEST(SerialChain, MatchesSimbodyOnTheLwr3Dcg) {
  const ArmModel shipped = load_shipped("dlr_lwr3.dcg");
  expect_matches_simbody(shipped, {}, "dcg all, shipped start angles");
  const ArmModel model = with_random_start_angles(shipped, 2);
  expect_matches_simbody(model, {}, "dcg all");
  expect_matches_simbody(model, {0, 1, 3}, "dcg 1,2,4");
  expect_matches_simbody(model, {4, 6}, "dcg 5,7");
}

TEST(SerialChain, MatchesSimbodyOnThePlanarArm) {
  const ArmModel model = with_random_start_angles(load_shipped("planar2.urdf"), 3);
  expect_matches_simbody(model, {}, "planar all");
  expect_matches_simbody(model, {1}, "planar 2");
  expect_matches_simbody(model, {1, 0}, "planar 2,1");
}

TEST(SerialChain, MatchesSimbodyWithAPrismaticJointAndATiltedAxis) {
  ArmModel model = testing::make_planar_arm({});
  model.joints[1].type = JointType::prismatic;
  model.joints[1].axis = Eigen::Vector3d(1.0, 0.5, -0.25).normalized();
  model.joints[0].axis = Eigen::Vector3d(0.3, -1.0, 0.2).normalized();
  model.joints[0].origin.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  model.joints[1].child_offset.translation() = Eigen::Vector3d(0.1, -0.2, 0.05);
  model.joints[1].child_offset.linear() = Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  model.joints[1].start_position = 0.15;
  expect_matches_simbody(model, {}, "prismatic all");
  expect_matches_simbody(model, {0}, "prismatic locked at 0.15 m");
  expect_matches_simbody(model, {1}, "prismatic only");
}

/// The chain's position and Jacobian by the general products only (every fixed rotation
/// multiplied, every joint rotation an AngleAxisd matrix, every vector product in full), folded
/// as SerialChain folds the path: the arithmetic SerialChain had before its joints about x, y or
/// z and its identity origins left out the terms that are exact zeros.
void calc_by_general_products(const ArmModel& model, const std::vector<int>& active, int link, const Eigen::Vector3d& offset,
                              const Eigen::VectorXd& q, Eigen::Vector3d& position, Eigen::Matrix3Xd& jacobian) {
  std::vector<int> parent_joint(model.links.size(), -1), path;
  for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) parent_joint[model.joints[j].child_link] = j;
  for (int l = link; l != model.root_link; l = model.joints[parent_joint[l]].parent_link) path.push_back(parent_joint[l]);
  std::reverse(path.begin(), path.end());
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();
  std::vector<std::pair<int, Eigen::Vector3d>> revolute_origins;  // column, joint origin in the world
  jacobian.setZero(3, static_cast<Eigen::Index>(active.size()));
  for (int j : path) {
    const Joint& joint = model.joints[j];
    pending = pending * joint.origin;
    const auto found = std::find(active.begin(), active.end(), j);
    if (found == active.end()) {
      pending = pending * calc_joint_motion(joint, joint.type == JointType::fixed ? 0.0 : joint.start_position) * joint.child_offset;
      continue;
    }
    const int column = static_cast<int>(found - active.begin());
    const Eigen::Vector3d axis = joint.axis.normalized();
    origin += rotation * pending.translation();
    rotation = rotation * pending.linear();
    if (joint.type == JointType::prismatic) {
      jacobian.col(column) = rotation * axis;
      origin += rotation * (q[column] * axis);
    } else {
      rotation = rotation * Eigen::AngleAxisd(q[column], axis).toRotationMatrix();
      jacobian.col(column) = rotation * axis;
      revolute_origins.emplace_back(column, origin);
    }
    pending = joint.child_offset;
  }
  position = origin + rotation * (pending * offset);
  for (const auto& [column, joint_origin] : revolute_origins) {
    const Eigen::Vector3d axis = jacobian.col(column);
    jacobian.col(column) = axis.cross(position - joint_origin);
  }
}

TEST(SerialChain, JointsAboutCoordinateAxesGiveTheGeneralProductsBitForBit) {
  // The LWR III's joints turn about x or z and its origins carry no rotation, so every step takes
  // the short path; the tilted planar arm (a general axis, a rotated origin, a prismatic joint)
  // takes the general one. Either way the numbers are the general products' to the last bit.
  ArmModel tilted = testing::make_planar_arm({});
  tilted.joints[0].axis = Eigen::Vector3d(0.3, -1.0, 0.2).normalized();
  tilted.joints[0].origin.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  tilted.joints[1].type = JointType::prismatic;
  tilted.joints[1].axis = Eigen::Vector3d(1.0, 0.5, -0.25).normalized();
  const std::vector<std::pair<ArmModel, std::vector<int>>> cases = {
      {load_shipped("dlr_lwr3.urdf"), {}}, {load_shipped("dlr_lwr3.urdf"), {0, 1, 3}}, {load_shipped("dlr_lwr3.dcg"), {}},
      {with_random_start_angles(load_shipped("dlr_lwr3.urdf"), 3), {1, 2, 4, 6}}, {tilted, {}}};
  RandomStream draws(17, "serial_chain_test.bit_for_bit");
  int short_paths = 0;
  for (const auto& [model, subset] : cases) {
    ArmDynamics dynamics(model, subset);
    const std::vector<int>& active = dynamics.active_joint_indices();
    const int link = model.end_effector.link;
    const SerialChain chain(model, active, link, model.end_effector.offset);
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::VectorXd q = draw_state(draws, model, active);
      Eigen::Vector3d position, expected_position;
      Eigen::Matrix3Xd jacobian, expected_jacobian;
      chain.calc_position_and_jacobian(q, position, jacobian);
      calc_by_general_products(model, active, link, model.end_effector.offset, q, expected_position, expected_jacobian);
      ASSERT_TRUE(position == expected_position) << model.name << " trial " << trial << ": " << (position - expected_position).transpose();
      ASSERT_TRUE(chain.calc_position(q) == expected_position) << model.name << " trial " << trial;
      ASSERT_TRUE(jacobian == expected_jacobian) << model.name << " trial " << trial << "\n" << jacobian - expected_jacobian;
    }
    for (int j : active) {
      for (int a = 0; a < 3; ++a) short_paths += model.joints[j].axis.normalized() == Eigen::Vector3d::Unit(a);
    }
  }
  EXPECT_GT(short_paths, 0);  // the LWR's axes are coordinate axes: the short path was compared
}

TEST(SerialChain, JacobianEqualsFiniteDifferencesOfThePosition) {
  const ArmModel model = load_shipped("dlr_lwr3.dcg");
  ArmDynamics dynamics(model, {0, 1, 3, 4, 5, 6});
  const SerialChain chain = make_end_effector_chain(dynamics);
  RandomStream draws(5, "serial_chain_test.finite_differences");
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = draw_state(draws, model, dynamics.active_joint_indices());
    const Eigen::Matrix3Xd jacobian = chain.calc_jacobian(q);
    for (int c = 0; c < chain.dof(); ++c) {
      Eigen::VectorXd plus = q, minus = q;
      plus[c] += h;
      minus[c] -= h;
      const Eigen::Vector3d difference = (chain.calc_position(plus) - chain.calc_position(minus)) / (2.0 * h);
      EXPECT_LT((difference - jacobian.col(c)).norm(), 1e-8) << "trial " << trial << " column " << c;
    }
  }
}

TEST(SerialChain, EndEffectorChainCarriesTheActiveJointsLimitsAndStartAngles) {
  const ArmModel model = load_shipped("dlr_lwr3.urdf");
  ArmDynamics dynamics(model, {3, 0, 1});
  const SerialChain chain = make_end_effector_chain(dynamics);
  EXPECT_EQ(chain.dof(), 3);
  EXPECT_EQ(chain.lower_limits(), dynamics.lower_limits());
  EXPECT_EQ(chain.upper_limits(), dynamics.upper_limits());
  EXPECT_EQ(chain.start_positions(), dynamics.start_positions());
  EXPECT_LT((chain.calc_position(chain.start_positions()) - dynamics.calc_end_effector_position(dynamics.start_positions())).norm(),
            1e-12);
}

TEST(SerialChain, RejectsBadIndicesAndWrongStateSizes) {
  const ArmModel model = load_shipped("planar2.urdf");
  EXPECT_THROW(SerialChain(model, {}, 7, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(SerialChain(model, {5}, 1, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(SerialChain(model, {0, 0}, 1, Eigen::Vector3d::Zero()), std::invalid_argument);
  const SerialChain chain(model, {0, 1}, 2, Eigen::Vector3d::Zero());
  EXPECT_THROW(chain.calc_position(Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace armfarm
