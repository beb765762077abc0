#pragma once
// The start posture of an arm: the angle (or position) each movable joint starts a job at, and
// where a locked joint stays. A file may give it (URDF <armfarm:start_position>, DCG a(...));
// a joint the file says nothing about gets calc_default_start_position. A job may replace the
// whole posture (the key start_posture, engine/experiment/job_model.hpp). Units: rad or m.
#include "engine/model/arm_model.hpp"

namespace armfarm {

/// The fraction of a joint's range kept free on either side of a default start position.
inline constexpr double kStartPostureMargin = 0.25;

/// The start position of a joint whose file gives none: 0, clamped into the middle half of its
/// range, [lower + m, upper − m] with m = kStartPostureMargin·(upper − lower); 0 when the joint
/// has no position limits. Why: 0 is the posture the maker's file is drawn in, usually a
/// meaningful one (the LWR III, iiwa and Panda stand straight up, the UR5e is stretched out), so
/// it is kept wherever it leaves a quarter of the range free on either side; a trajectory that
/// swings about the start then has room in both directions. A range that excludes 0 (the
/// Panda's elbow, [−3.07, −0.07] rad) or has 0 near one end starts a quarter of the range in
/// from the nearer end, inside the limits by construction. (Mid-range instead would move every
/// joint of an asymmetric range off the maker's zero.)
double calc_default_start_position(const Joint& joint);

}  // namespace armfarm
