#pragma once
// An independent inverse dynamics for the physics tests: a recursive Newton–Euler pass written
// here, in the world frame, on a URDF read by urdfdom directly (not through armfarm's loader).
// It shares nothing with armfarm's Simbody plant but the file: frames are composed from the
// joints' <origin> (quaternions as urdfdom gives them), links' inertias are turned by their
// <inertial> origin, gravity −9.81 m/s² along z enters as an upward acceleration of the root.
//   forward:  ω_c = ω_p + z q̇,  ω̇_c = ω̇_p + z q̈ + ω_p × z q̇  (revolute; prismatic adds
//             z q̈ + 2 ω_p × z q̇ to the linear acceleration), a_c = a_p + ω̇_p × r + ω_p × (ω_p × r)
//   per link: f = m a_com, n = I_w ω̇ + ω × I_w ω about the centre of mass
//   backward: the wrench of each subtree about its joint, τ = z·n (revolute) or z·f (prismatic)
// No friction, damping, limits or armature (add A q̈ separately).
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm::testing {

class RecursiveNewtonEuler {
 public:
  explicit RecursiveNewtonEuler(const std::string& urdf_path) : model_(urdf::parseURDFFile(urdf_path)) {
    if (!model_) throw std::runtime_error(urdf_path + ": urdfdom cannot parse it");
    collect_movable(model_->getRoot());
  }

  /// The movable joints in the order τ lists them: depth first from the root. (urdfdom keeps a
  /// link's child joints in name order, so this equals armfarm's file order only where a link has
  /// at most one movable child subtree, as every serial arm.)
  const std::vector<std::string>& joint_names() const { return names_; }

  /// τ (one per movable joint) for joint positions, velocities and accelerations in joint_names() order.
  Eigen::VectorXd calc_torques(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const {
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(names_.size()));
    Motion root;
    root.linear_acceleration = Eigen::Vector3d(0.0, 0.0, 9.81);  // gravity as an upward acceleration of the base
    visit(model_->getRoot(), root, q, qd, qdd, tau);
    return tau;
  }

 private:
  struct Motion {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // link frame in the world
    Eigen::Vector3d position = Eigen::Vector3d::Zero();      // link frame origin, world
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_acceleration = Eigen::Vector3d::Zero();
    Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // of the frame origin
  };
  struct Wrench {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // about the link frame origin
  };

  static Eigen::Matrix3d to_rotation(const urdf::Rotation& r) { return Eigen::Quaterniond(r.w, r.x, r.y, r.z).toRotationMatrix(); }
  static Eigen::Vector3d to_vector(const urdf::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
  static bool is_movable(const urdf::Joint& joint) {
    return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS || joint.type == urdf::Joint::PRISMATIC;
  }

  void collect_movable(const urdf::LinkConstSharedPtr& link) {
    for (const urdf::JointSharedPtr& joint : link->child_joints) {
      if (is_movable(*joint)) {
        index_[joint->name] = static_cast<Eigen::Index>(names_.size());
        names_.push_back(joint->name);
      }
      collect_movable(model_->getLink(joint->child_link_name));
    }
  }

  /// The wrench the subtree rooted at `link` needs from its parent joint, about the link origin.
  Wrench visit(const urdf::LinkConstSharedPtr& link, const Motion& m, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, Eigen::VectorXd& tau) const {
    Wrench total;
    if (link->inertial && link->inertial->mass > 0.0) {
      const urdf::Inertial& in = *link->inertial;
      const Eigen::Matrix3d frame = m.rotation * to_rotation(in.origin.rotation);
      Eigen::Matrix3d inertia;
      inertia << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Eigen::Matrix3d world_inertia = frame * inertia * frame.transpose();
      const Eigen::Vector3d r = m.rotation * to_vector(in.origin.position);  // origin → centre of mass
      const Eigen::Vector3d a_com =
          m.linear_acceleration + m.angular_acceleration.cross(r) + m.angular_velocity.cross(m.angular_velocity.cross(r));
      const Eigen::Vector3d f = in.mass * a_com;
      const Eigen::Vector3d n = world_inertia * m.angular_acceleration + m.angular_velocity.cross(world_inertia * m.angular_velocity);
      total.force += f;
      total.moment += n + r.cross(f);
    }
    for (const urdf::JointSharedPtr& joint : link->child_joints) {
      const bool movable = is_movable(*joint);
      const Eigen::Index i = movable ? index_.at(joint->name) : 0;
      const double qi = movable ? q[i] : 0.0, qdi = movable ? qd[i] : 0.0, qddi = movable ? qdd[i] : 0.0;
      const urdf::Pose& origin = joint->parent_to_joint_origin_transform;
      Motion c = m;
      c.rotation = m.rotation * to_rotation(origin.rotation);
      c.position = m.position + m.rotation * to_vector(origin.position);
      const Eigen::Vector3d z = movable ? Eigen::Vector3d(c.rotation * to_vector(joint->axis).normalized()) : Eigen::Vector3d::Zero();
      if (joint->type == urdf::Joint::PRISMATIC) c.position += z * qi;
      const Eigen::Vector3d r = c.position - m.position;
      c.linear_acceleration = m.linear_acceleration + m.angular_acceleration.cross(r) + m.angular_velocity.cross(m.angular_velocity.cross(r));
      if (joint->type == urdf::Joint::PRISMATIC) {
        c.linear_acceleration += z * qddi + 2.0 * m.angular_velocity.cross(z * qdi);
      } else if (movable) {
        c.rotation = c.rotation * Eigen::AngleAxisd(qi, to_vector(joint->axis).normalized()).toRotationMatrix();
        c.angular_velocity = m.angular_velocity + z * qdi;
        c.angular_acceleration = m.angular_acceleration + z * qddi + m.angular_velocity.cross(z * qdi);
      }
      const Wrench child = visit(model_->getLink(joint->child_link_name), c, q, qd, qdd, tau);
      if (movable) tau[i] = joint->type == urdf::Joint::PRISMATIC ? z.dot(child.force) : z.dot(child.moment);
      total.force += child.force;
      total.moment += child.moment + r.cross(child.force);
    }
    return total;
  }

  urdf::ModelInterfaceSharedPtr model_;
  std::vector<std::string> names_;
  std::map<std::string, Eigen::Index> index_;
};

}  // namespace armfarm::testing
