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

/// The gravity floor on the default gains: after gain_scale, kp_j of gains placed by
/// mass_bandwidth is at least this many times the gravity stiffness's row sum Σ_k |∂g_j/∂q_k| at
/// every posture the job visits (calc_gravity_kp_floor). With margin κ > 1, Gershgorin's theorem
/// puts every eigenvalue of Kp + ∂g/∂q at or above (1 − 1/κ)·min_j kp_j > 0: the feedback holds
/// the arm against gravity at each of those postures (engine/README.md, "Gravity floor").
inline constexpr double kGravityStiffnessMargin = 2.0;

/// The stiffness of the gravity torque at `q`: H = ∂g/∂q (n × n over the dynamics' active
/// joints, N·m/rad), g(q) the inverse dynamics at (q, 0, 0), by central differences of step
/// 1e-6 rad (or m). H is the Hessian of the potential energy (symmetric up to the differences'
/// error); a linearised arm under PD obeys M ë = −(Kp + H) e − Kd ė.
Eigen::MatrixXd make_gravity_stiffness(ArmDynamics& dynamics, const Eigen::VectorXd& q);

/// The kp floor (n, N·m/rad, after gain_scale): `margin` × the largest row sum Σ_k |H_jk| over
/// `stiffness` (one H per posture, each n × n). Empty `stiffness`: zeros of size `n`. Pure.
Eigen::VectorXd calc_gravity_kp_floor(const std::vector<Eigen::MatrixXd>& stiffness, int n, double margin = kGravityStiffnessMargin);

/// How far a joint's inertia may grow along the job's postures above the one its default gains
/// are placed on: gains placed on M_jj keep the bandwidth ω·√(M_jj/M) at inertia M, so with
/// M ≤ kPlacementInertiaRatio·M_ref the bandwidth stays at least ω/√2 at every posture visited
/// (kp per unit inertia at least half the placed one). At 4 (ω/2) one low-gain quick-start job of
/// the Kinova Gen3 still diverged (models/README.md).
inline constexpr double kPlacementInertiaRatio = 2.0;

/// The inertia (n) the default gains are placed on: the start posture's mass-matrix diagonal,
/// raised to max_inertia / kPlacementInertiaRatio where a visited posture's diagonal
/// (`max_inertia`, the largest over the postures) exceeds that ratio; unchanged, bit for bit,
/// elsewhere. Pure.
Eigen::VectorXd calc_placement_inertia(const Eigen::VectorXd& start_inertia, const Eigen::VectorXd& max_inertia);

/// Whether the gains are placed on the arm (both kp and kd by mass_bandwidth), so that the
/// placement inertia and the gravity floor apply (gains the user sets, and appendix D's, are run
/// as given).
bool has_placed_gains(const ControlConfig& control);

/// Full-scale gains that run at `scale` with kp at least `kp_floor` (n, after the scale): where
/// scale·kp_j < kp_floor_j, kp_j becomes kp_floor_j / scale and kd_j grows by √ of kp_j's factor
/// (the damping ratio of the placement kept); the other joints are returned unchanged, bit for
/// bit. An empty floor or scale ≤ 0 returns `gains`. Pure.
PdGains calc_floored_gains(const PdGains& gains, const Eigen::VectorXd& kp_floor, double scale);

/// The factor kd is scaled by for a gain scale: √gain_scale when keep_damping_ratio (the
/// damping ratio of kp, kd is kept), else gain_scale (as kp; ζ falls by √gain_scale).
double calc_kd_scale(double gain_scale, bool keep_damping_ratio);

/// Expands a 0- or 1-element vector to `size` entries (`fallback` for an empty one); throws
/// std::invalid_argument naming `field` when the size is neither 0, 1 nor `size`.
Eigen::VectorXd expand_per_joint(const Eigen::VectorXd& values, int size, double fallback, const char* field);

}  // namespace armfarm
