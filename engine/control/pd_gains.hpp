#pragma once
// The PD gains of a job: given per joint, or placed by a rule that keeps sample-and-hold
// control stable at the control period (see ControlConfig). Units: N·m/rad, N·m·s/rad.
#include "engine/control/control_config.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Core>

namespace armfarm {

struct PdGains {
  Eigen::VectorXd kp;  ///< n_active × 1
  Eigen::VectorXd kd;  ///< n_active × 1
};

/// Full-scale gains (gain_scale not applied): the configured ones (a 1-element vector is
/// broadcast) or, where empty, kp = M_jj·ω², kd = 2ζ·M_jj·ω from the mass matrix diagonal at the
/// start posture. Throws std::invalid_argument ("control.kp: ...") for a wrong size or a
/// negative gain.
PdGains make_pd_gains(const ControlConfig& control, ArmDynamics& dynamics);

/// The factor kd is scaled by for a gain scale: √gain_scale when keep_damping_ratio (the
/// damping ratio of kp, kd is kept), else gain_scale (as kp; ζ falls by √gain_scale).
double calc_kd_scale(double gain_scale, bool keep_damping_ratio);

/// Expands a 0- or 1-element vector to `size` entries (`fallback` for an empty one); throws
/// std::invalid_argument naming `field` when the size is neither 0, 1 nor `size`.
Eigen::VectorXd expand_per_joint(const Eigen::VectorXd& values, int size, double fallback, const char* field);

}  // namespace armfarm
