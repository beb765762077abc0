#pragma once
// Desired velocities and accelerations of a sampled joint path (units: rad, s).
#include "engine/trajectory/trajectory.hpp"

namespace armfarm {

/// Fills trajectory.qd and trajectory.qdd from trajectory.q (samples dt apart):
/// backward_difference as the thesis (first sample: zero), smoothed by Savitzky–Golay
/// derivative filters (window, order), analytic by second-order central differences
/// (one-sided at the ends, or wrapped when `periodic`).
void fill_derivatives(JointTrajectory& trajectory, Differentiation method, bool periodic, int window, int order);

}  // namespace armfarm
