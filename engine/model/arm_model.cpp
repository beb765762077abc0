#include "engine/model/arm_model.hpp"

namespace armfarm {

std::vector<int> ArmModel::movable_joints() const {
  std::vector<int> indices;
  for (int i = 0; i < static_cast<int>(joints.size()); ++i) {
    if (joints[i].type != JointType::fixed) indices.push_back(i);
  }
  return indices;
}

int ArmModel::find_link(const std::string& link_name) const {
  for (int i = 0; i < static_cast<int>(links.size()); ++i) {
    if (links[i].name == link_name) return i;
  }
  return -1;
}

int ArmModel::find_joint(const std::string& joint_name) const {
  for (int i = 0; i < static_cast<int>(joints.size()); ++i) {
    if (joints[i].name == joint_name) return i;
  }
  return -1;
}

Eigen::Isometry3d calc_joint_motion(const Joint& joint, double position) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (joint.type == JointType::prismatic) {
    motion.translation() = position * joint.axis.normalized();
  } else if (joint.type != JointType::fixed) {
    motion.linear() = Eigen::AngleAxisd(position, joint.axis.normalized()).toRotationMatrix();
  }
  return motion;
}

double ArmModel::total_mass() const {
  double mass = 0.0;
  for (const Link& link : links) {
    if (!link.fixed_to_world) mass += link.inertial.mass;
  }
  return mass;
}

}  // namespace armfarm
