#pragma once
// Shared by the model tests: paths, an error-capturing loader call, and a forward-kinematics
// helper written independently of the engine (Eigen only) to compare URDF and DCG arms.
#include "engine/model/arm_model.hpp"
#include "engine/model/model_loading.hpp"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace armfarm::test {

inline std::string data_path(const std::string& relative) { return std::string(ARMFARM_TEST_DATA_DIR) + "/models/" + relative; }
inline std::string models_path(const std::string& relative) { return std::string(ARMFARM_SOURCE_DIR) + "/models/" + relative; }

/// The ModelError message of loading `path`, or "" when it loads.
inline std::string load_error(const std::string& path) {
  try {
    load_arm_model(path);
  } catch (const ModelError& error) {
    return error.what();
  }
  return "";
}

/// The ModelError message of loading `path` with the end effector `choice`, or "" when it loads
/// (end_effector_test.cpp and urdf_loading_test.cpp).
inline std::string load_error(const std::string& path, const EndEffectorConfig& choice) {
  try {
    load_arm_model(path, choice);
  } catch (const ModelError& error) {
    return error.what();
  }
  return "";
}

/// World frames of every link and every joint frame (after `origin`, before the motion) for
/// movable-joint positions q (in ArmModel::movable_joints order).
struct ForwardKinematics {
  std::vector<Eigen::Isometry3d> links;
  std::vector<Eigen::Isometry3d> joints;  // indexed like ArmModel::joints
};

inline ForwardKinematics calc_forward_kinematics(const ArmModel& model, const std::vector<double>& q) {
  ForwardKinematics fk;
  fk.links.assign(model.links.size(), Eigen::Isometry3d::Identity());
  fk.joints.assign(model.joints.size(), Eigen::Isometry3d::Identity());
  std::size_t next = 0;
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    fk.joints[j] = fk.links[joint.parent_link] * joint.origin;
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (joint.type == JointType::revolute || joint.type == JointType::continuous) {
      motion.linear() = Eigen::AngleAxisd(q.at(next++), joint.axis).toRotationMatrix();
    } else if (joint.type == JointType::prismatic) {
      motion.translation() = q.at(next++) * joint.axis;
    }
    fk.links[joint.child_link] = fk.joints[j] * motion * joint.child_offset;
  }
  return fk;
}

}  // namespace armfarm::test
