#pragma once
// What a diverged pass's message tells the user to change: the key, and a value that would have
// worked where armfarm can compute one — the steps the step-stability criterion picks at the
// posture where the pass diverged, or a slower trajectory when the desired motion itself asks a
// joint for more than its velocity limit.
#include "engine/control/composite_controller.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <Eigen/Core>

#include <string>

namespace armfarm {

/// "; … set pd_substeps to 4 (…why…)": what to change. `q`: the plant's last finite posture
/// (n × 1; empty: unknown) and `q_desired` the desired posture then; `controller`: the pass's.
std::string make_divergence_advice(JobSetup& setup, const CompositeController& controller, const JointTrajectory& trajectory,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& q_desired);

}  // namespace armfarm
