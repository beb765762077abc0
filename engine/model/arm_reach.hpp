#pragma once
// How far an arm reaches: a kinematic summary used by `armfarm model info` and the tests.
// Units: metres.
#include "engine/model/arm_model.hpp"

#include <vector>

namespace armfarm {

/// World poses of every link frame with every joint at zero (links index ArmModel::links).
std::vector<Eigen::Isometry3d> calc_zero_configuration_link_poses(const ArmModel& model);

/// Reach of the arm: along the path from the root to the end-effector link, the sum of the
/// distances between successive movable-joint origins plus the distance from the last one to
/// the end-effector point, all at zero configuration. An upper bound on how far the end effector
/// can get from the first joint (reached when the arm is stretched).
double calc_reach(const ArmModel& model);

}  // namespace armfarm
