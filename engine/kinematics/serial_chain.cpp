#include "engine/kinematics/serial_chain.hpp"

#include "engine/physics/arm_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

/// Joint frames with active joints on the path above this many use a heap buffer for their origins.
constexpr int kStackSteps = 32;

/// The index of the unit coordinate vector `axis` is exactly, or −1.
int find_coordinate_axis(const Eigen::Vector3d& axis) {
  for (int a = 0; a < 3; ++a) {
    if (axis == Eigen::Vector3d::Unit(a)) return a;
  }
  return -1;
}

/// origin += rotation · t, the terms of t's zero components left out (each would add an exact
/// zero to the sum; the others are added in Eigen's order, column 0 first).
inline void add_rotated(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& t, Eigen::Vector3d& origin) {
  Eigen::Vector3d sum;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    if (t[k] == 0.0) continue;
    if (any) {
      sum += rotation.col(k) * t[k];
    } else {
      sum = rotation.col(k) * t[k];
      any = true;
    }
  }
  if (any) origin += sum;
}

/// rotation ← rotation · R, R = AngleAxisd(angle, e_a).toRotationMatrix(): with (p, r) the
/// other two axes in cyclic order, R has c at (p, p) and (r, r), s at (r, p), −s at (p, r),
/// (1 − c) + c at (a, a) (Eigen's diagonal formula) and exact zeros elsewhere.
inline void rotate_about_coordinate_axis(Eigen::Matrix3d& rotation, int a, double angle) {
  const int p = (a + 1) % 3, r = (a + 2) % 3;
  const double s = std::sin(angle), c = std::cos(angle);
  const Eigen::Vector3d column_p = rotation.col(p) * c + rotation.col(r) * s;
  const Eigen::Vector3d column_r = rotation.col(p) * (-s) + rotation.col(r) * c;
  rotation.col(p) = column_p;
  rotation.col(r) = column_r;
  rotation.col(a) *= (1.0 - c) + c;
}

}  // namespace

SerialChain::SerialChain(const ArmModel& model, const std::vector<int>& active_joints, int link,
                         const Eigen::Vector3d& offset)
    : dof_(static_cast<int>(active_joints.size())) {
  const int n_links = static_cast<int>(model.links.size());
  const int n_joints = static_cast<int>(model.joints.size());
  if (link < 0 || link >= n_links) {
    throw std::invalid_argument(model.source_file + ": kinematic chain to link " + std::to_string(link) + ", which does not exist");
  }
  std::vector<int> column_of(model.joints.size(), -1);
  const double infinity = std::numeric_limits<double>::infinity();
  lower_.resize(dof_);
  upper_.resize(dof_);
  start_.resize(dof_);
  for (int c = 0; c < dof_; ++c) {
    const int j = active_joints[c];
    if (j < 0 || j >= n_joints) throw std::invalid_argument(model.source_file + ": active joint index " + std::to_string(j) + " out of range");
    const Joint& joint = model.joints[j];
    if (joint.type == JointType::fixed) throw std::invalid_argument(model.source_file + ": joint " + joint.name + " is fixed and cannot be active");
    if (column_of[j] >= 0) throw std::invalid_argument(model.source_file + ": joint " + joint.name + " is listed twice");
    column_of[j] = c;
    lower_[c] = joint.has_position_limits ? joint.lower : -infinity;
    upper_[c] = joint.has_position_limits ? joint.upper : infinity;
    start_[c] = joint.start_position;
  }
  // The joints from the root to `link`, root first.
  std::vector<int> parent_joint(model.links.size(), -1);
  for (int j = 0; j < n_joints; ++j) parent_joint[model.joints[j].child_link] = j;
  std::vector<int> path;
  for (int l = link; l != model.root_link;) {
    const int j = parent_joint[l];
    if (j < 0 || static_cast<int>(path.size()) > n_joints) {
      throw std::invalid_argument(model.source_file + ": link " + model.links[link].name + " is not connected to the root link");
    }
    path.push_back(j);
    l = model.joints[j].parent_link;
  }
  std::reverse(path.begin(), path.end());
  // Fold every fixed piece between two active joints into one transform.
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();
  for (int j : path) {
    const Joint& joint = model.joints[j];
    pending = pending * joint.origin;
    if (column_of[j] < 0) {
      pending = pending * calc_joint_motion(joint, joint.type == JointType::fixed ? 0.0 : joint.start_position) * joint.child_offset;
      continue;
    }
    Step step;
    step.rotation = pending.linear();
    step.translation = pending.translation();
    step.axis = joint.axis.normalized();
    step.prismatic = joint.type == JointType::prismatic;
    step.column = column_of[j];
    step.identity_rotation = step.rotation == Eigen::Matrix3d::Identity();
    step.axis_index = step.prismatic ? -1 : find_coordinate_axis(step.axis);
    steps_.push_back(step);
    pending = joint.child_offset;
  }
  point_ = pending * offset;
}

template <typename Visit>
Eigen::Vector3d SerialChain::walk(const Eigen::VectorXd& q, Visit&& visit) const {
  if (q.size() != dof_) {
    throw std::invalid_argument("kinematic chain: expected " + std::to_string(dof_) + " joint positions, got " +
                                std::to_string(q.size()));
  }
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    const Step& step = steps_[k];
    add_rotated(rotation, step.translation, origin);
    if (!step.identity_rotation) rotation = rotation * step.rotation;
    const double angle = q[step.column];
    if (step.prismatic) {
      visit(k, step, rotation, origin);  // the axis does not move with the slide
      origin += rotation * (angle * step.axis);
    } else if (step.axis_index >= 0) {
      rotate_about_coordinate_axis(rotation, step.axis_index, angle);
      visit(k, step, rotation, origin);
    } else {
      rotation = rotation * Eigen::AngleAxisd(angle, step.axis).toRotationMatrix();
      visit(k, step, rotation, origin);
    }
  }
  Eigen::Vector3d point = origin;
  add_rotated(rotation, point_, point);
  return point;
}

Eigen::Vector3d SerialChain::calc_position(const Eigen::VectorXd& q) const {
  return walk(q, [](std::size_t, const Step&, const Eigen::Matrix3d&, const Eigen::Vector3d&) {});
}

void SerialChain::calc_position_and_jacobian(const Eigen::VectorXd& q, Eigen::Vector3d& position,
                                             Eigen::Matrix3Xd& jacobian) const {
  jacobian.setZero(3, dof_);
  const int n = static_cast<int>(steps_.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, kStackSteps> small_buffer;
  Eigen::Matrix3Xd large_buffer;
  double* buffer = nullptr;
  if (n <= kStackSteps) {
    small_buffer.resize(3, n);
    buffer = small_buffer.data();
  } else {
    large_buffer.resize(3, n);
    buffer = large_buffer.data();
  }
  Eigen::Map<Eigen::Matrix3Xd> origins(buffer, 3, n);  // joint origins, world frame
  // First the world axes (in the Jacobian's columns) and origins, then the lever arms.
  position = walk(q, [&](std::size_t k, const Step& step, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& origin) {
    if (step.axis_index >= 0) {
      jacobian.col(step.column) = rotation.col(step.axis_index);  // rotation · e_a, without its zero terms
    } else {
      jacobian.col(step.column) = rotation * step.axis;
    }
    origins.col(k) = origin;
  });
  for (int k = 0; k < n; ++k) {
    const Step& step = steps_[k];
    if (!step.prismatic) {
      const Eigen::Vector3d axis = jacobian.col(step.column);
      jacobian.col(step.column) = axis.cross(position - origins.col(k));
    }
  }
}

Eigen::Matrix3Xd SerialChain::calc_jacobian(const Eigen::VectorXd& q) const {
  Eigen::Vector3d position;
  Eigen::Matrix3Xd jacobian(3, dof_);
  calc_position_and_jacobian(q, position, jacobian);
  return jacobian;
}

SerialChain make_end_effector_chain(const ArmDynamics& dynamics) {
  const ArmModel& model = dynamics.model();
  return SerialChain(model, dynamics.active_joint_indices(), model.end_effector.link, model.end_effector.offset);
}

}  // namespace armfarm
