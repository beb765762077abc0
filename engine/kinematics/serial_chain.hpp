#pragma once
// Forward kinematics and the translational Jacobian of a point on a link, computed directly
// from the ArmModel's joint transforms (no Simbody): the path of joints from the root link to
// the point's link, with the active joints moving and every other joint held where
// ArmDynamics/ArmSimulation weld it (locked joints at their start_position, fixed joints at 0).
// Consecutive fixed transforms are folded into one at construction, so evaluating the chain
// costs one rotation per active joint on the path (about a microsecond for the 7-DOF arm).
//
// Units: m and rad (prismatic joints: m). Frames: positions and Jacobians in the world frame
// (the root link's frame, as in ArmDynamics). Joint vectors have one entry per active joint, in
// the order the chain was built with (ArmDynamics's active-joint order).
#include "engine/model/arm_model.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace armfarm {

class ArmDynamics;

/// An immutable description of the kinematic path to one point. Cheap to copy, safe to share
/// across threads; all calc_ functions are const and allocate nothing when given sized outputs.
class SerialChain {
 public:
  /// The chain from `model`'s root to `offset` (m, link frame) on `link`. `active_joints` are
  /// indices into model.joints (as ArmDynamics::active_joint_indices), one per column of q;
  /// active joints that are not on the path give zero Jacobian columns. Throws
  /// std::invalid_argument for a link or joint index out of range or a fixed joint listed active.
  SerialChain(const ArmModel& model, const std::vector<int>& active_joints, int link, const Eigen::Vector3d& offset);

  int dof() const { return dof_; }  ///< number of active joints (columns of q and of the Jacobian)

  /// World position of the point at joint angles q (dof × 1).
  Eigen::Vector3d calc_position(const Eigen::VectorXd& q) const;
  /// The position and d(position)/dq (3 × dof, world frame) at q; `jacobian` is resized if needed.
  void calc_position_and_jacobian(const Eigen::VectorXd& q, Eigen::Vector3d& position, Eigen::Matrix3Xd& jacobian) const;
  Eigen::Matrix3Xd calc_jacobian(const Eigen::VectorXd& q) const;

  /// Position limits of the active joints (dof × 1): -inf / +inf where a joint has none.
  const Eigen::VectorXd& lower_limits() const { return lower_; }
  const Eigen::VectorXd& upper_limits() const { return upper_; }
  /// The active joints' start angles (the rest posture), dof × 1.
  const Eigen::VectorXd& start_positions() const { return start_; }

 private:
  /// One active joint on the path: the fixed transform from the previous active joint's moved
  /// frame (or the world) to this joint's frame, then the motion about/along `axis`.
  struct Step {
    Eigen::Matrix3d rotation;     ///< of the fixed transform before the joint
    Eigen::Vector3d translation;  ///< of the fixed transform before the joint, m
    Eigen::Vector3d axis;         ///< unit, joint frame
    bool prismatic = false;
    int column = 0;               ///< index into q
    /// The fixed rotation is exactly I (every joint origin of an arm without rpy): its product,
    /// which would add only exact zeros to each entry, is skipped.
    bool identity_rotation = false;
    /// 0, 1 or 2 when `axis` is exactly that unit vector (a revolute joint about x, y or z): the
    /// joint's rotation moves two columns of the frame (and scales the third by the (1 − c) + c
    /// that Eigen's AngleAxis puts on the diagonal), the same sums without the terms that are
    /// exact zeros. −1: the general AngleAxis product.
    int axis_index = -1;
  };

  /// Walks the path; calls visit(step, frame) with the joint frame after its motion.
  template <typename Visit>
  Eigen::Vector3d walk(const Eigen::VectorXd& q, Visit&& visit) const;

  int dof_ = 0;
  std::vector<Step> steps_;
  Eigen::Vector3d point_ = Eigen::Vector3d::Zero();  ///< the point in the last active joint's moved frame (or the world)
  Eigen::VectorXd lower_, upper_, start_;
};

/// The end-effector chain of `dynamics`'s model and active joints.
SerialChain make_end_effector_chain(const ArmDynamics& dynamics);

}  // namespace armfarm
