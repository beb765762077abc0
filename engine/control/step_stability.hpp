#pragma once
// Stable by construction: whether a job's sample-and-hold PD loop and its fixed-step
// integrator are stable at the steps it is run with, decided from the model's linearised joint
// dynamics before the job runs, and the coarsest steps that are (what `auto` picks).
// engine/README.md ("Stable by construction") derives the bounds.
//
// The plant at a posture q, velocities near 0 (Coriolis terms vanish; gravity's stiffness and
// Coulomb friction are left out):
//   M q̈ = τ − B q̇,   M = M(q) + A (armature included, n × n), B = diag(b) (viscous damping),
//   τ = −Kp (q − q_d) − Kd (q̇ − q̇_d), computed at the start of each PD period h = dt / P and
//   held over it; the plant integrated by classical Runge–Kutta 4 in S steps h_i = h / S.
// Over one PD period the error state x = (q − q_d, q̇ − q̇_d) maps to F x (F exactly as RK4
// composes it); the loop is stable while the spectral radius ρ(F) ≤ 1. For one joint without
// damping (RK4 is exact on q̈ = const) that is the closed form
//   kd·h/M < 2   and   0 < kp·h²/M < 2·kd·h/M,
// and the integrator on its own (τ held, the passive decay q̈ = −(b/M) q̇) needs
//   λ_max(M⁻¹B)·h_i < 2.7853 (RK4's stability region on the negative real axis; b·h_i/M for one joint).
// Units: SI and radians. Vectors have one entry per active joint.
#include <Eigen/Core>

#include <vector>

namespace armfarm {

/// |1 + z + z²/2 + z³/6 + z⁴/24| ≤ 1 for real z in [−kRk4RealBound, 0]: where classical RK4 damps a
/// decaying mode instead of amplifying it.
inline constexpr double kRk4RealBound = 2.785293563405282;

/// `auto` picks steps that are stable at this many times their size: a margin for postures
/// between those checked, the neglected gravity stiffness and friction. (2 would move the LWR
/// III's default job to 2 PD periods per tick: along its sine the fastest coupled mode reaches
/// kd·h/M = 1.11, which 1.5 × keeps below 2.)
inline constexpr double kStepMargin = 1.5;

/// The caps of the search, the keys' ranges (simulation_config.hpp).
inline constexpr int kMaxPdSubsteps = 100;
inline constexpr int kMaxIntegratorSteps = 1000;

/// The linearised plant of a job's active joints at one posture.
struct LoopPlant {
  Eigen::MatrixXd mass;     ///< M(q) + A, n × n, kg·m² (symmetric positive definite)
  Eigen::VectorXd damping;  ///< b, n, N·m·s/rad (≥ 0)
};

/// One controller's gains as the plant feels them (gain_scale and the kd scale applied), n each.
struct LoopGains {
  Eigen::VectorXd kp;  ///< N·m/rad
  Eigen::VectorXd kd;  ///< N·m·s/rad
};

/// How the plant is stepped over a control tick of dt.
struct LoopSteps {
  double dt = 0.01;          ///< s, the control tick
  int pd_substeps = 1;       ///< P: PD periods per tick (h = dt / P)
  int integrator_steps = 1;  ///< S: RK4 steps per PD period (h_i = h / S)
  /// false: an adaptive integrator, which follows the period's dynamics closely; then only the
  /// PD loop is judged (on a fine RK4 of the period) and S does not matter.
  bool fixed_step = true;
};

/// The criterion's numbers for one plant, one controller and one choice of steps.
struct LoopStability {
  /// ρ(F) per PD period with the loop closed (≤ 1: stable); 0 when judged open-loop.
  double spectral_radius = 0.0;
  /// λ_max(M⁻¹B)·h_i, the passive decay per RK4 step (stable below kRk4RealBound); 0 for adaptive integrators.
  double passive_step_ratio = 0.0;
  /// The active joint (0-based) that dominates the least stable mode, and its closed-form
  /// ratios on the diagonal M_jj: kd·h/M_jj (bound 2), kp·h²/M_jj (bound 2·kd·h/M_jj), b·h_i/M_jj.
  int joint = 0;
  double inertia = 0.0;  ///< M_jj, kg·m²
  double kd_ratio = 0.0;
  double kp_ratio = 0.0;
  double damping_ratio = 0.0;
  /// λ_max(M⁻¹Kd)·h: kd·h/M of the fastest coupled mode (equals the largest joint's kd·h/M_jj
  /// when M is diagonal; coupling through M can raise it well above).
  double modal_kd_ratio = 0.0;

  bool loop_stable() const;
  bool integrator_stable() const;
  bool stable() const { return loop_stable() && integrator_stable(); }
};

/// The criterion for `plant` under `gains` (nullptr: open loop, only the integrator is judged)
/// at `steps`. Pure; throws std::invalid_argument for mismatched sizes or a mass matrix that is
/// not positive definite.
LoopStability calc_loop_stability(const LoopPlant& plant, const LoopGains* gains, const LoopSteps& steps);

/// The steps `auto` picks and whether they satisfy the criterion.
struct StepChoice {
  int pd_substeps = 1;
  int integrator_steps = 1;
  bool found = true;  ///< false: no steps within the caps are stable (the caps are returned)
};

/// The fewest PD periods P, then the fewest RK4 steps S per period, such that every plant of
/// `plants` under every controller of `controllers` (none: open loop) is stable at
/// `margin` × (h, h_i). `fixed_pd` / `fixed_integrator` > 0 hold that value (an explicit
/// setting); 0 lets it be chosen. Adaptive integrators (`fixed_step` false) keep S at 1.
StepChoice calc_stable_steps(const std::vector<LoopPlant>& plants, const std::vector<LoopGains>& controllers, double dt,
                             bool fixed_step, int fixed_pd, int fixed_integrator, double margin = kStepMargin);

}  // namespace armfarm
