#pragma once
// Checks the invariants every ArmModel promises (see arm_model.hpp) and reports the first
// violation as a one-line ModelError `<file>:<line>: <element>: <what>` (or `<file>: <element>:
// <what>` when the loader knows no line for that element).
#include "engine/model/arm_model.hpp"

#include <map>
#include <string>

namespace armfarm {

/// Where each link and joint was written in the source file (1-based lines), for messages.
struct ModelSourceLines {
  std::map<std::string, int> links;
  std::map<std::string, int> joints;
};

/// Throws ModelError on: bad link/joint indices, a link with several parents, cycles, links
/// not connected to the root, joints out of tree order, non-positive mass on a link that a joint
/// moves (mass 0 is allowed on links welded by fixed joints or fixed to the world), an inertia
/// that is not symmetric positive definite or violates the triangle inequality, NaN/Inf
/// anywhere, a zero or non-unit axis, lower > upper, negative damping/friction/armature,
/// non-positive effort/velocity limits, a start position outside the limits, and an invalid
/// end effector (link -1 passes: not chosen yet, see end_effector.hpp).
void validate_arm_model(const ArmModel& model, const ModelSourceLines& lines = {});

}  // namespace armfarm
