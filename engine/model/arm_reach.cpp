#include "engine/model/arm_reach.hpp"

namespace armfarm {

std::vector<Eigen::Isometry3d> calc_zero_configuration_link_poses(const ArmModel& model) {
  std::vector<Eigen::Isometry3d> poses(model.links.size(), Eigen::Isometry3d::Identity());
  for (const Joint& joint : model.joints) {  // tree order: parents come first
    poses[joint.child_link] = poses[joint.parent_link] * joint.origin * joint.child_offset;
  }
  return poses;
}

double calc_reach(const ArmModel& model) {
  const std::vector<Eigen::Isometry3d> poses = calc_zero_configuration_link_poses(model);
  std::vector<int> parent_joint(model.links.size(), -1);
  for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) parent_joint[model.joints[j].child_link] = j;

  // Movable joint origins from the end effector back to the root.
  std::vector<Eigen::Vector3d> points{poses[model.end_effector.link] * model.end_effector.offset};
  for (int j = parent_joint[model.end_effector.link]; j >= 0; j = parent_joint[model.joints[j].parent_link]) {
    const Joint& joint = model.joints[j];
    if (joint.type != JointType::fixed) points.push_back((poses[joint.parent_link] * joint.origin).translation());
  }
  double reach = 0.0;
  for (std::size_t k = 1; k < points.size(); ++k) reach += (points[k] - points[k - 1]).norm();
  return reach;
}

}  // namespace armfarm
