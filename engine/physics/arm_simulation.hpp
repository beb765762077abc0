#pragma once
// The physics of one job: an ArmModel turned into a Simbody multibody system, stepped one
// control tick at a time with joint torques held constant over the tick, plus the exact
// rigid-body calculations (inverse dynamics, kinematics, Jacobian, mass matrix) that the
// controllers, inverse kinematics and metrics need.
//
// Only engine/physics/simbody_*.cpp include Simbody; this header is Simbody-free (pImpl).
// Units: SI and radians. Vectors of joint quantities have one entry per *active* joint, in
// the order of ArmSimulationOptions::active_joints. Task-space points are in the world frame.
#include "engine/model/arm_model.hpp"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace armfarm {

/// How the plant is integrated over a tick. The Simbody integrators are adaptive and restarted
/// every tick; runge_kutta_4 is armfarm's own fixed-step classical Runge–Kutta on (q, q̇), the
/// armature equation solved directly at each stage (no Simbody forward dynamics, no restart).
enum class IntegratorKind { runge_kutta_merson, runge_kutta_3, runge_kutta_feldberg, explicit_euler, semi_explicit_euler2, verlet, cpodes,
                            runge_kutta_4 };

/// Extra mass rigidly attached to the end effector (model mismatch, thesis section 3.1).
struct Payload {
  double mass = 0.0;                                     ///< kg; 0 = none
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      ///< centre of mass, end-effector link frame
  double radius_of_gyration = 0.0;                       ///< m; inertia = mass·r²·I about its centre
};

/// Passive joint forces added on top of (or replacing) the model's, per active joint.
struct JointFrictionOverride {
  Eigen::VectorXd viscous;  ///< N·m·s/rad, empty = the model's damping
  Eigen::VectorXd coulomb;  ///< N·m, empty = the model's friction
};

/// How a job's plant is built. A plain description; defaults are the documented defaults.
struct ArmSimulationOptions {
  std::vector<int> active_joints;  ///< indices into ArmModel::movable_joints(); empty = all. Others are locked at start_position.
  IntegratorKind integrator = IntegratorKind::runge_kutta_4;  // engine/README.md, "Integrator choice"
  double accuracy = 1e-5;          ///< relative accuracy of adaptive integrators
  double fixed_step = 0.0;         ///< s; > 0 forces a fixed step for the Simbody integrators
  int steps_per_tick = 1;          ///< runge_kutta_4: equal steps per call of ArmSimulation::step
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  ///< m/s², world frame
  bool soft_joint_limits = true;   ///< stiff spring-damper outside [lower, upper]
  double limit_stiffness = 2000.0; ///< N·m/rad
  double limit_damping = 20.0;     ///< N·m·s/rad
  double coulomb_velocity_scale = 0.01;  ///< rad/s; friction = F·tanh(q̇ / scale)
  Payload payload;
  JointFrictionOverride friction_override;
};

/// Mutable state of one job's plant. Not thread-safe; one instance per job and thread.
class ArmSimulation {
 public:
  ArmSimulation(const ArmModel& model, const ArmSimulationOptions& options);
  ~ArmSimulation();
  ArmSimulation(ArmSimulation&&) noexcept;
  ArmSimulation& operator=(ArmSimulation&&) noexcept;

  int dof() const;  ///< number of active joints
  const std::vector<int>& active_joint_indices() const;  ///< indices into ArmModel::joints

  /// Sets time, joint angles and velocities (n_active × 1 each).
  void set_state(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  /// Applies `tau` (n_active × 1, N·m) held constant for `duration` seconds and advances the
  /// state. Throws std::runtime_error if the integrator fails.
  void step(const Eigen::VectorXd& tau, double duration);

  double time() const;
  const Eigen::VectorXd& q() const;
  const Eigen::VectorXd& qd() const;
  const Eigen::VectorXd& qdd() const;  ///< acceleration at the current state under the last applied torque

  /// Changes the plant mid-run (payload, friction); the state (t, q, q̇) is kept.
  void set_payload(const Payload& payload);
  void set_friction_override(const JointFrictionOverride& friction);

  /// Kinetic + gravitational potential energy of the plant (J), armature included.
  double calc_energy() const;

  /// Number of integrator steps taken so far (for cost measurements).
  long integrator_steps() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Exact rigid-body calculations on the *nominal* model (no friction override; a payload
/// only when given, e.g. to score learners against the true plant), for any active-joint
/// subset. Holds scratch state; one instance per job and thread.
class ArmDynamics {
 public:
  ArmDynamics(const ArmModel& model, std::vector<int> active_joints = {}, const Payload& payload = {});
  ~ArmDynamics();
  ArmDynamics(ArmDynamics&&) noexcept;
  ArmDynamics& operator=(ArmDynamics&&) noexcept;

  int dof() const;
  const ArmModel& model() const;                         ///< the model it was built from
  const std::vector<int>& active_joint_indices() const;  ///< indices into ArmModel::joints, one per active joint

  /// τ = (M(q) + diag(armature)) q̈ + C(q, q̇) q̇ + g(q): the torques (n × 1) that produce q̈
  /// at (q, q̇) with no friction, damping or limit forces.
  Eigen::VectorXd calc_inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd);
  /// Forward dynamics with the same model: q̈ for torques τ (n × 1).
  Eigen::VectorXd calc_forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau);
  /// M(q) + diag(armature), n × n.
  Eigen::MatrixXd calc_mass_matrix(const Eigen::VectorXd& q);
  /// World position of `offset` (link frame) on `link`; default: the end effector.
  Eigen::Vector3d calc_point_position(const Eigen::VectorXd& q, int link, const Eigen::Vector3d& offset);
  Eigen::Vector3d calc_end_effector_position(const Eigen::VectorXd& q);
  /// d(position)/dq, 3 × n, world frame.
  Eigen::Matrix3Xd calc_point_jacobian(const Eigen::VectorXd& q, int link, const Eigen::Vector3d& offset);
  Eigen::Matrix3Xd calc_end_effector_jacobian(const Eigen::VectorXd& q);

  /// Start angles, position limits, effort and velocity limits of the active joints (n × 1).
  Eigen::VectorXd start_positions() const;
  Eigen::VectorXd lower_limits() const;   ///< -inf where unlimited
  Eigen::VectorXd upper_limits() const;   ///< +inf where unlimited
  Eigen::VectorXd effort_limits() const;
  Eigen::VectorXd velocity_limits() const;
  Eigen::VectorXd viscous_damping() const;   ///< the model's joint damping, N·m·s/rad
  Eigen::VectorXd coulomb_friction() const;  ///< the model's joint friction, N·m

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace armfarm
