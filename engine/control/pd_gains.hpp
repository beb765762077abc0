#pragma once
// The PD gains of a job: given per joint, or placed by a rule that keeps sample-and-hold
// control stable at the control period (see ControlConfig). Units: N·m/rad, N·m·s/rad.
#include "engine/control/control_config.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Core>

#include <vector>

namespace armfarm {

struct PdGains {
  Eigen::VectorXd kp;  ///< n_active × 1
  Eigen::VectorXd kd;  ///< n_active × 1
};

/// Appendix D's paramfile PID lines (the thesis's joints 0-5; I = 0 in every line): kp in
/// N·m/rad, kd in N·m·s/rad, for joint numbers 1-6. Joint 7 (the LWR III's last wrist roll; the
/// thesis's arm had six joints) takes joint 6's line.
/// Stability: the torque is held over a PD period h, and a joint of inertia I is stable under
/// held damping only while kd·h/I < 2. On the LWR III's wrist (I ≈ 0.11 kg·m² with armature)
/// kd·h/I ≈ 6.8 at h = 10 ms: the gains diverge within 0.05 s (measured); at h = 1 ms
/// (pd_substeps 10) they run (measured stable on appendix D's sine, full scale and 0.2).
PdGains make_appendix_d_gains(const std::vector<int>& joint_numbers);

/// Full-scale gains (gain_scale not applied): the configured ones (a 1-element vector is
/// broadcast) or, where empty, those of control.gain_set: kp = M_jj·ω², kd = 2ζ·M_jj·ω from the
/// mass matrix diagonal at the start posture, or appendix D's for the active `joint_numbers`
/// (1-based). Throws std::invalid_argument ("control.kp: ...") for a wrong size or a negative gain.
PdGains make_pd_gains(const ControlConfig& control, ArmDynamics& dynamics, const std::vector<int>& joint_numbers);
/// The same from `inertia`, the mass-matrix diagonal (armature included) at the start posture
/// (n × 1). Pure.
PdGains calc_pd_gains(const ControlConfig& control, const Eigen::VectorXd& inertia, const std::vector<int>& joint_numbers);

/// The factor kd is scaled by for a gain scale: √gain_scale when keep_damping_ratio (the
/// damping ratio of kp, kd is kept), else gain_scale (as kp; ζ falls by √gain_scale).
double calc_kd_scale(double gain_scale, bool keep_damping_ratio);

/// Expands a 0- or 1-element vector to `size` entries (`fallback` for an empty one); throws
/// std::invalid_argument naming `field` when the size is neither 0, 1 nor `size`.
Eigen::VectorXd expand_per_joint(const Eigen::VectorXd& values, int size, double fallback, const char* field);

}  // namespace armfarm
