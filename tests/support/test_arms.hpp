#pragma once
// Arms for the engine tests (physics, kinematics, trajectories, control, experiments): a 2-link
// planar arm built inline (its closed-form dynamics: tests/engine/physics/arm_dynamics_test.cpp), a
// one-link arm, and the shipped 7-DOF LWR III model.
#include "engine/model/arm_model.hpp"
#include "engine/model/model_loading.hpp"

#include <limits>
#include <string>

namespace armfarm::testing {

/// Parameters of the planar arm: joint axes along −y, so a positive angle lifts the link from
/// +x towards +z (the usual counter-clockwise angle in the x–z plane); gravity −z.
struct PlanarArmParameters {
  double length1 = 1.0, com1 = 0.45, mass1 = 2.0, inertia1 = 0.18;  ///< inertia about the COM, joint axis
  double com2 = 0.38, mass2 = 1.5, inertia2 = 0.09;
  double armature1 = 0.0, armature2 = 0.0;
};

inline ArmModel make_planar_arm(const PlanarArmParameters& p) {
  ArmModel model;
  model.name = "planar2_inline";
  model.source_file = "(inline)";
  model.links.resize(3);
  model.links[0].name = "base";
  model.links[0].fixed_to_world = true;
  auto make_link = [](const std::string& name, double mass, double com, double inertia) {
    Link link;
    link.name = name;
    link.inertial.mass = mass;
    link.inertial.com = Eigen::Vector3d(com, 0, 0);
    link.inertial.inertia = Eigen::Vector3d(0.01, inertia, inertia).asDiagonal();
    return link;
  };
  model.links[1] = make_link("upper", p.mass1, p.com1, p.inertia1);
  model.links[2] = make_link("fore", p.mass2, p.com2, p.inertia2);
  for (int i = 0; i < 2; ++i) {
    Joint joint;
    joint.name = "joint" + std::to_string(i + 1);
    joint.parent_link = i;
    joint.child_link = i + 1;
    joint.axis = -Eigen::Vector3d::UnitY();
    joint.origin.translation() = i == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(p.length1, 0, 0);
    joint.armature = i == 0 ? p.armature1 : p.armature2;
    joint.effort_limit = joint.velocity_limit = std::numeric_limits<double>::infinity();
    model.joints.push_back(joint);
  }
  model.end_effector = {2, Eigen::Vector3d(0.8, 0, 0)};
  return model;
}

/// One link on one revolute joint at the world origin, turning about `axis`: `mass` at `com`
/// (link frame), `inertia` about the COM, the joint's `armature` and viscous `damping`, no limits;
/// the end effector at the COM. The closed-form cases of the control tests (turntable, pendulum).
inline ArmModel make_one_link_arm(const std::string& name, double mass, const Eigen::Vector3d& com, const Eigen::Matrix3d& inertia,
                                  const Eigen::Vector3d& axis, double armature = 0.0, double damping = 0.0) {
  ArmModel model;
  model.name = name;
  model.source_file = "(inline)";
  model.links.resize(2);
  model.links[0].name = "base";
  model.links[0].fixed_to_world = true;
  model.links[1].name = "link";
  model.links[1].inertial.mass = mass;
  model.links[1].inertial.com = com;
  model.links[1].inertial.inertia = inertia;
  Joint joint;
  joint.name = "joint";
  joint.parent_link = 0;
  joint.child_link = 1;
  joint.axis = axis;
  joint.armature = armature;
  joint.damping = damping;
  joint.effort_limit = joint.velocity_limit = std::numeric_limits<double>::infinity();
  model.joints.push_back(joint);
  model.end_effector = {1, com};
  return model;
}

inline ArmModel load_lwr3() { return load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf"); }

}  // namespace armfarm::testing
