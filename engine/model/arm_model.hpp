#pragma once
// The immutable description of a serial (tree) robot arm: links with their mass properties,
// joints with their placement, axis, limits and passive dynamics. Built once by a loader
// (URDF, DCG) and shared read-only by every job that runs on it.
//
// Units: SI (m, kg, s, N, N·m) and radians everywhere. Frames: every link has a frame; a
// joint's frame is placed in its parent link's frame by `origin`, the joint moves its frame
// about/along `axis` (in the joint frame), and the child link's frame sits at `child_offset`
// in the moved joint frame (identity for URDF; the DCG format's transforms after `||`).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// Mass properties of a link: mass (kg), centre of mass in the link frame (m), and the
/// inertia tensor about the centre of mass, expressed in the link frame (kg·m²).
struct Inertial {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

/// A geometric primitive of a link, kept for drawing and for documenting where the mass
/// properties came from. Pose is in the link frame.
struct LinkShape {
  enum class Kind { sphere, box, capped_cylinder, mesh };
  Kind kind = Kind::sphere;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< sphere: (r,0,0); box: (sx,sy,sz); capped cylinder: (r, length, 0)
  std::string mesh_file;                           ///< resolved path, mesh only
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d colour = Eigen::Vector3d::Constant(0.7);  ///< RGB in [0,1]
};

struct Link {
  std::string name;
  Inertial inertial;
  std::vector<LinkShape> shapes;
  bool fixed_to_world = false;  ///< DCG `fix`: the body is welded to the world frame.
};

enum class JointType { revolute, continuous, prismatic, fixed };

/// A joint between two links. Angles in rad (prismatic: m). Limits are only meaningful when
/// `has_position_limits`; effort (N·m or N) and velocity (rad/s or m/s) limits are +inf when
/// the file gives none.
struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  int parent_link = -1;  ///< index into ArmModel::links
  int child_link = -1;   ///< index into ArmModel::links
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();        ///< joint frame in the parent link frame at q = 0
  Eigen::Isometry3d child_offset = Eigen::Isometry3d::Identity();  ///< child link frame in the moved joint frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();                 ///< unit vector, joint frame
  bool has_position_limits = false;
  double lower = 0.0;
  double upper = 0.0;
  double effort_limit = 0.0;    ///< +inf when unlimited
  double velocity_limit = 0.0;  ///< +inf when unlimited
  double damping = 0.0;         ///< viscous, N·m·s/rad
  double friction = 0.0;        ///< Coulomb-like, N·m
  double armature = 0.0;        ///< reflected rotor inertia about the axis, kg·m² (adds to the mass matrix diagonal)
  double start_position = 0.0;  ///< initial angle or position (start_posture.hpp)
  /// Whether the file gave start_position (URDF <armfarm:start_position>, DCG a(...)); else it is
  /// calc_default_start_position's (start_posture.hpp).
  bool start_position_from_file = false;
};

/// The point that tracks task-space targets: a link and an offset in that link's frame.
struct EndEffector {
  int link = -1;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

/// A validated arm. Invariants (checked by validate_arm_model): links and joints form a tree
/// rooted at `root_link`; joints are ordered so that a joint's parent link is the root or the
/// child of an earlier joint; masses are positive and finite; inertias are symmetric positive
/// definite and satisfy the triangle inequality; axes are unit vectors.
struct ArmModel {
  std::string name;
  std::string source_file;  ///< the file it was loaded from, for messages
  /// Every file the loader read, as it opened them: `source_file` first, then referenced files
  /// (meshes) in order of first use, each once. What a job's key hashes for its model.
  std::vector<std::string> input_files;
  std::vector<Link> links;
  std::vector<Joint> joints;
  int root_link = 0;
  EndEffector end_effector;
  /// Elements the loader skipped that a strict reading refuses, one line each ("file:line: <x>
  /// in <link> of link 'y' is not a URDF element"); see check_strict_model (model_loading.hpp).
  std::vector<std::string> warnings;

  /// Indices into `joints` of the joints that move (not `fixed`), in tree order. The
  /// "joint numbers" users give (active joint lists, per-joint gains) index this list.
  std::vector<int> movable_joints() const;
  int find_link(const std::string& link_name) const;    ///< -1 if absent
  int find_joint(const std::string& joint_name) const;  ///< -1 if absent
  double total_mass() const;                            ///< links not fixed to the world
};

/// The motion of `joint` at `position` (rad or m) in its joint frame: a rotation about, or a
/// translation along, its axis; identity for a fixed joint. A joint's child frame sits at
/// origin · motion · child_offset in its parent link's frame.
Eigen::Isometry3d calc_joint_motion(const Joint& joint, double position);

}  // namespace armfarm
