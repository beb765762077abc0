// The one module that talks to Simbody: an ArmModel becomes a MultibodySystem whose only
// force element (JointDynamicsForce) computes every generalized force itself, so that the
// joints' armature (reflected rotor inertia) can enter the dynamics exactly:
//
//   (M(q) + A) q̈ + c(q, q̇) = τ_held + τ_passive(q, q̇) + g(q)
//
// Simbody's forward dynamics solves M q̈ = f − c for the mobility forces f we apply. Given the
// q̈* that solves the armature equation, applying f = τ_held + τ_passive + g − A q̈* makes
// Simbody produce exactly q̈* (M q̈* = (M + A) q̈* − A q̈*). A is diagonal, n ≤ 7, so the
// extra n×n solve per force evaluation is cheap next to the integrator's work.
#include "engine/physics/arm_simulation.hpp"

#include <Simbody.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace armfarm {

namespace {

SimTK::Vec3 to_simtk(const Eigen::Vector3d& v) { return SimTK::Vec3(v.x(), v.y(), v.z()); }

SimTK::Transform to_simtk(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d r = pose.linear();
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
  return SimTK::Transform(SimTK::Rotation(m, true), to_simtk(pose.translation()));
}

// A rotation taking `from` (a unit axis of Simbody's mobilizer) onto the joint's axis.
Eigen::Isometry3d make_axis_alignment(const Eigen::Vector3d& from, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
  alignment.linear() = Eigen::Quaterniond::FromTwoVectors(from, axis.normalized()).toRotationMatrix();
  return alignment;
}

SimTK::MassProperties make_mass_properties(const Inertial& inertial) {
  const Eigen::Matrix3d& i = inertial.inertia;
  const SimTK::Inertia central(SimTK::Vec3(i(0, 0), i(1, 1), i(2, 2)), SimTK::Vec3(i(0, 1), i(0, 2), i(1, 2)));
  const SimTK::Vec3 com = to_simtk(inertial.com);
  return SimTK::MassProperties(inertial.mass, com, central.shiftFromMassCenter(com, inertial.mass));
}

/// Per-active-joint parameters of the passive forces, in mobility (u) order.
struct JointForceParameters {
  Eigen::VectorXd armature;
  Eigen::VectorXd viscous;
  Eigen::VectorXd coulomb;
  Eigen::VectorXd lower;
  Eigen::VectorXd upper;
};

/// The system of one arm: matter, forces, and the maps from active joints to mobilities.
struct ArmSystem {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Vec3 gravity;
  std::vector<SimTK::MobilizedBodyIndex> link_bodies;  ///< per model link; invalid when not built
  std::vector<SimTK::MobilizedBodyIndex> active_bodies;  ///< per active joint (user order)
  std::vector<int> active_joint_indices;                 ///< into ArmModel::joints (user order)
  std::vector<int> mobility_of_active;                   ///< u index of each active joint
  JointForceParameters parameters;                       ///< in user (active) order
  const ArmSimulationOptions* options = nullptr;
  Eigen::VectorXd held_torque;                           ///< user order, read by the force element
  /// Work space of the per-stage calculations (M, the rigid residual), sized on first use so that
  /// a stage allocates no SimTK vector of its own. Not shared across threads (one system per job).
  struct Scratch {
    SimTK::Matrix mass;                             ///< nu × nu, M as calcM writes it
    SimTK::Vector zero_mobility_forces, udot, residual;  ///< nu
    SimTK::Vector_<SimTK::SpatialVec> body_forces;  ///< per body, ground's entry zero
  };
  mutable Scratch scratch;
};

/// Realizes what the stage calculations read at the state's (q, u): the tree's position and then
/// velocity kinematics (body poses, velocities, the velocity-dependent inertial terms). This is
/// what System::realize(state, Stage::Velocity) computes for the matter, without the stage loop
/// over every subsystem (the force subsystem, whose one element acts at Dynamics, and the event
/// handlers have nothing to do at Position or Velocity here). M, the residual, gravity's body
/// forces and the station kinematics read only these caches, so their numbers are the same bits.
void realize_kinematics(const ArmSystem& arm, const SimTK::State& state) {
  arm.matter.realizePositionKinematics(state);
  arm.matter.realizeVelocityKinematics(state);
}

/// Computes all generalized forces of the arm, armature included (see the file comment).
class JointDynamicsForce : public SimTK::Force::Custom::Implementation {
 public:
  explicit JointDynamicsForce(const ArmSystem& arm) : arm_(arm) {}

  void calcForce(const SimTK::State& state, SimTK::Vector_<SimTK::SpatialVec>&, SimTK::Vector_<SimTK::Vec3>&,
                 SimTK::Vector& mobility_forces) const override {
    const int n = static_cast<int>(arm_.active_bodies.size());
    if (n == 0) return;
    const Eigen::VectorXd total = calc_total_generalized_force(arm_, state);
    const Eigen::VectorXd& armature = arm_.parameters.armature;
    Eigen::VectorXd applied = total;
    if (armature.any()) {
      const Eigen::VectorXd udot = calc_armature_acceleration(arm_, state, total);
      applied -= armature.cwiseProduct(udot);
    }
    for (int j = 0; j < n; ++j) mobility_forces[arm_.mobility_of_active[j]] += applied[j];
  }

  SimTK::Real calcPotentialEnergy(const SimTK::State&) const override { return 0.0; }

  /// τ_held + passive + limits + gravity as generalized forces, user order.
  static Eigen::VectorXd calc_total_generalized_force(const ArmSystem& arm, const SimTK::State& state) {
    const int n = static_cast<int>(arm.active_bodies.size());
    return add_passive_and_gravity(arm, state, arm.held_torque.size() == n ? arm.held_torque : Eigen::VectorXd::Zero(n));
  }

  /// `total` (n, user order) plus the passive, limit and gravity generalized forces.
  static Eigen::VectorXd add_passive_and_gravity(const ArmSystem& arm, const SimTK::State& state, Eigen::VectorXd total) {
    add_passive(arm, state, total);
    const Eigen::VectorXd gravity = calc_gravity_generalized_force(arm, state);
    return total + gravity;
  }

  /// Adds the passive (damping, friction) and limit generalized forces to `total` (n, user order).
  static void add_passive(const ArmSystem& arm, const SimTK::State& state, Eigen::VectorXd& total) {
    const int n = static_cast<int>(arm.active_bodies.size());
    const ArmSimulationOptions& options = *arm.options;
    const SimTK::Vector& u = state.getU();
    const SimTK::Vector& q = state.getQ();
    for (int j = 0; j < n; ++j) {
      const int m = arm.mobility_of_active[j];
      const double velocity = u[m];
      total[j] -= arm.parameters.viscous[j] * velocity;
      total[j] -= arm.parameters.coulomb[j] * std::tanh(velocity / options.coulomb_velocity_scale);
      if (options.soft_joint_limits) {
        const double below = arm.parameters.lower[j] - q[m];
        const double above = q[m] - arm.parameters.upper[j];
        if (below > 0.0) total[j] += options.limit_stiffness * below - options.limit_damping * std::min(velocity, 0.0);
        if (above > 0.0) total[j] -= options.limit_stiffness * above + options.limit_damping * std::max(velocity, 0.0);
      }
    }
  }

  /// Gravity as one spatial force per body (about its origin, ground frame) into `body_forces`
  /// (sized to the bodies, ground's entry zero). Needs position kinematics.
  static void calc_gravity_body_forces(const ArmSystem& arm, const SimTK::State& state,
                                       SimTK::Vector_<SimTK::SpatialVec>& body_forces) {
    const int n_bodies = arm.matter.getNumBodies();
    if (body_forces.size() != n_bodies) body_forces.resize(n_bodies);
    body_forces[0] = SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0));
    for (SimTK::MobilizedBodyIndex b(1); b < n_bodies; ++b) {
      const SimTK::MobilizedBody& body = arm.matter.getMobilizedBody(b);
      const SimTK::MassProperties& mass = body.getBodyMassProperties(state);
      const SimTK::Vec3 com_offset = body.getBodyRotation(state) * mass.getMassCenter();
      const SimTK::Vec3 weight = mass.getMass() * arm.gravity;
      body_forces[b] = SimTK::SpatialVec(com_offset % weight, weight);
    }
  }

  static SimTK::Vector_<SimTK::SpatialVec> calc_gravity_body_forces(const ArmSystem& arm, const SimTK::State& state) {
    SimTK::Vector_<SimTK::SpatialVec> body_forces;
    calc_gravity_body_forces(arm, state, body_forces);
    return body_forces;
  }

  /// M q̈ + c(q, q̇) − g(q) for q̈ (user order; empty = 0) in one inverse-dynamics pass with gravity
  /// applied as body forces, into `result` (user order). Needs velocity kinematics. Zero applied
  /// mobility forces and a zero q̈ are passed as zero vectors rather than empty ones: Simbody
  /// then makes no zero vector of its own, and adds and multiplies the same zeros.
  static void calc_rigid_residual(const ArmSystem& arm, const SimTK::State& state, const Eigen::VectorXd& qdd,
                                  Eigen::VectorXd& result) {
    ArmSystem::Scratch& scratch = arm.scratch;
    const int nu = arm.matter.getNumMobilities();
    if (scratch.zero_mobility_forces.size() != nu) {
      scratch.zero_mobility_forces.resize(nu);
      scratch.zero_mobility_forces = 0.0;
      scratch.udot.resize(nu);
    }
    scratch.udot = 0.0;
    for (std::size_t j = 0; j < static_cast<std::size_t>(qdd.size()); ++j) {
      scratch.udot[arm.mobility_of_active[j]] = qdd[static_cast<Eigen::Index>(j)];
    }
    calc_gravity_body_forces(arm, state, scratch.body_forces);
    arm.matter.calcResidualForceIgnoringConstraints(state, scratch.zero_mobility_forces, scratch.body_forces, scratch.udot,
                                                    scratch.residual);
    result.resize(static_cast<Eigen::Index>(arm.active_bodies.size()));
    for (std::size_t j = 0; j < arm.active_bodies.size(); ++j) result[j] = scratch.residual[arm.mobility_of_active[j]];
  }

  static Eigen::VectorXd calc_rigid_residual(const ArmSystem& arm, const SimTK::State& state, const Eigen::VectorXd& qdd) {
    Eigen::VectorXd result;
    calc_rigid_residual(arm, state, qdd, result);
    return result;
  }

  /// g(q): generalized forces of gravity on every body, user order. Needs Position stage.
  static Eigen::VectorXd calc_gravity_generalized_force(const ArmSystem& arm, const SimTK::State& state) {
    const SimTK::Vector_<SimTK::SpatialVec> body_forces = calc_gravity_body_forces(arm, state);
    SimTK::Vector generalized;
    arm.matter.multiplyBySystemJacobianTranspose(state, body_forces, generalized);
    Eigen::VectorXd result(arm.active_bodies.size());
    for (std::size_t j = 0; j < arm.active_bodies.size(); ++j) result[j] = generalized[arm.mobility_of_active[j]];
    return result;
  }

  /// c(q, q̇): Coriolis, centrifugal and gyroscopic generalized forces, user order.
  static Eigen::VectorXd calc_bias_force(const ArmSystem& arm, const SimTK::State& state) {
    SimTK::Vector residual;
    arm.matter.calcResidualForceIgnoringConstraints(state, SimTK::Vector(), SimTK::Vector_<SimTK::SpatialVec>(),
                                                    SimTK::Vector(), residual);
    Eigen::VectorXd result(arm.active_bodies.size());
    for (std::size_t j = 0; j < arm.active_bodies.size(); ++j) result[j] = residual[arm.mobility_of_active[j]];
    return result;
  }

  /// M(q) in user order (without armature) into `result`. Needs position kinematics. calcM into a
  /// matrix kept across calls: it forms M e_i column by column with the matter's own O(n) product,
  /// the numbers of the public multiplyByM, without that wrapper's two helper vectors per call
  /// (callgrind: 47.4k → 43.5k instructions per 7-DOF M, bench_physics BM_MassMatrix).
  static void calc_rigid_mass_matrix(const ArmSystem& arm, const SimTK::State& state, Eigen::MatrixXd& result) {
    ArmSystem::Scratch& scratch = arm.scratch;
    arm.matter.calcM(state, scratch.mass);
    const int n = static_cast<int>(arm.active_bodies.size());
    result.resize(n, n);
    // An owner Matrix is one column-major block: read it directly, not through an element call each.
    const int nu = scratch.mass.nrow();
    const double* mass = scratch.mass.getContiguousScalarData();
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) result(i, j) = mass[arm.mobility_of_active[i] + nu * arm.mobility_of_active[j]];
    }
  }

  static Eigen::MatrixXd calc_rigid_mass_matrix(const ArmSystem& arm, const SimTK::State& state) {
    Eigen::MatrixXd result;
    calc_rigid_mass_matrix(arm, state, result);
    return result;
  }

  /// q̈ = (M + A)⁻¹ (f − c) for total generalized force f, user order.
  static Eigen::VectorXd calc_armature_acceleration(const ArmSystem& arm, const SimTK::State& state,
                                                    const Eigen::VectorXd& total) {
    Eigen::MatrixXd mass = calc_rigid_mass_matrix(arm, state);
    mass.diagonal() += arm.parameters.armature;
    return mass.llt().solve(total - calc_bias_force(arm, state));
  }

 private:
  const ArmSystem& arm_;
};

std::vector<int> resolve_active_joints(const ArmModel& model, const std::vector<int>& active) {
  const std::vector<int> movable = model.movable_joints();
  std::vector<int> joints;
  if (active.empty()) return movable;
  for (int index : active) {
    if (index < 0 || index >= static_cast<int>(movable.size())) {
      throw std::invalid_argument("active joint " + std::to_string(index) + " is not one of the " +
                                  std::to_string(movable.size()) + " movable joints of " + model.name);
    }
    if (std::find(joints.begin(), joints.end(), movable[index]) != joints.end()) {
      throw std::invalid_argument("active joint " + std::to_string(index) + " is listed twice");
    }
    joints.push_back(movable[index]);
  }
  return joints;
}

/// Adds the body that joint `joint_index` of `model` carries, hinged on its already built parent:
/// welded where the joint holds it when the joint is not active (a fixed joint at 0, a locked one
/// at its start position), on a pin (revolute) or slider (prismatic) about its axis when it is.
/// Records the body as its child link's and, for an active joint, as that joint's.
void add_joint_body(const ArmModel& model, int joint_index, ArmSystem& arm) {
  const Joint& joint = model.joints[joint_index];
  const SimTK::MobilizedBodyIndex parent_index = arm.link_bodies[joint.parent_link];
  if (!parent_index.isValid()) throw std::invalid_argument(model.source_file + ": joint " + joint.name + " has no built parent");
  SimTK::MobilizedBody& parent = arm.matter.updMobilizedBody(parent_index);
  const Link& child = model.links[joint.child_link];
  const SimTK::Body::Rigid body(make_mass_properties(child.inertial));
  const auto active = std::find(arm.active_joint_indices.begin(), arm.active_joint_indices.end(), joint_index);
  SimTK::MobilizedBodyIndex built;
  if (active == arm.active_joint_indices.end()) {
    // Fixed or locked: weld the child where the joint holds it at its start position.
    const double position = joint.type == JointType::fixed ? 0.0 : joint.start_position;
    const Eigen::Isometry3d pose = joint.origin * calc_joint_motion(joint, position) * joint.child_offset;
    built = SimTK::MobilizedBody::Weld(parent, to_simtk(pose), body, SimTK::Transform()).getMobilizedBodyIndex();
  } else {
    const bool prismatic = joint.type == JointType::prismatic;
    const Eigen::Isometry3d alignment =
        make_axis_alignment(prismatic ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ(), joint.axis);
    const SimTK::Transform in_parent = to_simtk(joint.origin * alignment);
    const SimTK::Transform in_child = to_simtk(joint.child_offset.inverse() * alignment);
    if (prismatic) {
      built = SimTK::MobilizedBody::Slider(parent, in_parent, body, in_child).getMobilizedBodyIndex();
    } else {
      built = SimTK::MobilizedBody::Pin(parent, in_parent, body, in_child).getMobilizedBodyIndex();
    }
    arm.active_bodies[active - arm.active_joint_indices.begin()] = built;
  }
  arm.link_bodies[joint.child_link] = built;
}

/// Welds the payload (a point mass with the given radius of gyration, kg and m) to the
/// end-effector link at its offset; nothing when its mass is 0.
void add_payload(const ArmModel& model, const Payload& payload_options, ArmSystem& arm) {
  if (!(payload_options.mass > 0.0)) return;
  const SimTK::MobilizedBodyIndex carrier = arm.link_bodies.at(model.end_effector.link);
  const double r = payload_options.radius_of_gyration;
  const double inertia = payload_options.mass * r * r;
  Inertial payload;
  payload.mass = payload_options.mass;
  payload.inertia = Eigen::Matrix3d::Identity() * inertia;
  const SimTK::Body::Rigid body(make_mass_properties(payload));
  SimTK::MobilizedBody::Weld(arm.matter.updMobilizedBody(carrier), SimTK::Transform(to_simtk(payload_options.offset)), body,
                             SimTK::Transform());
}

/// The passive-force parameters of the active joints (user order): the model's armature, damping,
/// friction and position limits (±inf without limits), with the friction override's damping and
/// friction where it gives one value per active joint. Throws for an override of another size.
JointForceParameters make_joint_force_parameters(const ArmModel& model, const std::vector<int>& active_joint_indices,
                                                 const JointFrictionOverride& friction) {
  const int n = static_cast<int>(active_joint_indices.size());
  JointForceParameters parameters;
  parameters.armature.resize(n);
  parameters.viscous.resize(n);
  parameters.coulomb.resize(n);
  parameters.lower.resize(n);
  parameters.upper.resize(n);
  const double infinity = std::numeric_limits<double>::infinity();
  for (int j = 0; j < n; ++j) {
    const Joint& joint = model.joints[active_joint_indices[j]];
    parameters.armature[j] = joint.armature;
    parameters.viscous[j] = joint.damping;
    parameters.coulomb[j] = joint.friction;
    parameters.lower[j] = joint.has_position_limits ? joint.lower : -infinity;
    parameters.upper[j] = joint.has_position_limits ? joint.upper : infinity;
  }
  if (friction.viscous.size() == n) parameters.viscous = friction.viscous;
  if (friction.coulomb.size() == n) parameters.coulomb = friction.coulomb;
  if ((friction.viscous.size() != 0 && friction.viscous.size() != n) ||
      (friction.coulomb.size() != 0 && friction.coulomb.size() != n)) {
    throw std::invalid_argument("friction override needs one value per active joint (" + std::to_string(n) + ")");
  }
  return parameters;
}

/// Adds the one force element, realizes the topology and records each active joint's u index.
void finish_arm_system(ArmSystem& arm) {
  const int n = static_cast<int>(arm.active_bodies.size());
  SimTK::Force::Custom(arm.forces, new JointDynamicsForce(arm));
  arm.system.realizeTopology();
  arm.mobility_of_active.resize(n);
  const SimTK::State& state = arm.system.getDefaultState();
  for (int j = 0; j < n; ++j) {
    arm.mobility_of_active[j] = arm.matter.getMobilizedBody(arm.active_bodies[j]).getFirstUIndex(state);
  }
}

/// Builds the system: a body per joint in the model's joint order (each parent before its child),
/// the payload, the passive-force parameters, then the force element and the topology.
/// `payload` and `friction` are the plant's; ArmDynamics passes none.
std::unique_ptr<ArmSystem> make_arm_system(const ArmModel& model, const ArmSimulationOptions& options) {
  auto arm = std::make_unique<ArmSystem>();
  arm->options = &options;
  arm->gravity = to_simtk(options.gravity);
  arm->active_joint_indices = resolve_active_joints(model, options.active_joints);
  const int n = static_cast<int>(arm->active_joint_indices.size());
  arm->link_bodies.assign(model.links.size(), SimTK::MobilizedBodyIndex());
  arm->active_bodies.assign(n, SimTK::MobilizedBodyIndex());
  arm->link_bodies[model.root_link] = SimTK::GroundIndex;
  for (int joint_index = 0; joint_index < static_cast<int>(model.joints.size()); ++joint_index) {
    add_joint_body(model, joint_index, *arm);
  }
  add_payload(model, options.payload, *arm);
  arm->parameters = make_joint_force_parameters(model, arm->active_joint_indices, options.friction_override);
  arm->held_torque = Eigen::VectorXd::Zero(n);
  finish_arm_system(*arm);
  return arm;
}

void write_joint_state(const ArmSystem& arm, SimTK::State& state, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const int n = static_cast<int>(arm.active_bodies.size());
  if (q.size() != n || qd.size() != n) {
    throw std::invalid_argument("expected " + std::to_string(n) + " joint positions and velocities, got " +
                                std::to_string(q.size()) + " and " + std::to_string(qd.size()));
  }
  // One updQ/updU each: every call invalidates the stages and q- or u-dependent caches anew.
  SimTK::Vector& positions = state.updQ();
  SimTK::Vector& velocities = state.updU();
  for (int j = 0; j < n; ++j) {
    positions[arm.mobility_of_active[j]] = q[j];  // 1-dof mobilizers: q index = u index
    velocities[arm.mobility_of_active[j]] = qd[j];
  }
}

Eigen::VectorXd read_mobilities(const ArmSystem& arm, const SimTK::Vector& values) {
  Eigen::VectorXd result(arm.active_bodies.size());
  for (std::size_t j = 0; j < arm.active_bodies.size(); ++j) result[j] = values[arm.mobility_of_active[j]];
  return result;
}

std::unique_ptr<SimTK::Integrator> make_integrator(const SimTK::MultibodySystem& system, const ArmSimulationOptions& options) {
  std::unique_ptr<SimTK::Integrator> integrator;
  switch (options.integrator) {
    case IntegratorKind::runge_kutta_merson: integrator = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system); break;
    case IntegratorKind::runge_kutta_3: integrator = std::make_unique<SimTK::RungeKutta3Integrator>(system); break;
    case IntegratorKind::runge_kutta_feldberg: integrator = std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system); break;
    case IntegratorKind::explicit_euler: integrator = std::make_unique<SimTK::ExplicitEulerIntegrator>(system); break;
    case IntegratorKind::semi_explicit_euler2: integrator = std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system); break;
    case IntegratorKind::verlet: integrator = std::make_unique<SimTK::VerletIntegrator>(system); break;
    case IntegratorKind::cpodes: integrator = std::make_unique<SimTK::CPodesIntegrator>(system); break;
    case IntegratorKind::runge_kutta_4:  // armfarm's own (ArmSimulation::Impl); Merson takes its ticks at a joint limit
      integrator = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
      break;
  }
  integrator->setAccuracy(options.accuracy);
  if (options.fixed_step > 0.0) integrator->setFixedStepSize(options.fixed_step);
  integrator->setAllowInterpolation(false);  // stop exactly at the end of each control tick
  integrator->setReturnEveryInternalStep(false);
  return integrator;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
struct ArmSimulation::Impl {
  const ArmModel* model = nullptr;
  ArmSimulationOptions options;
  std::unique_ptr<ArmSystem> arm;
  SimTK::State state;
  std::unique_ptr<SimTK::Integrator> integrator;
  Eigen::VectorXd q, qd, qdd;
  long integrator_steps = 0;  ///< summed over ticks (each tick restarts the integrator)

  /// runge_kutta_4: the torque-free part of the armature equation at the current state,
  /// q̈ = (M + A)⁻¹ (τ + free_force) with free_force = passive + limits + g − c; valid while the
  /// state is the one it was computed at (the next tick's first stage reuses it).
  struct StageDynamics {
    Eigen::LLT<Eigen::MatrixXd> mass;  ///< M + A factored
    Eigen::VectorXd free_force;
  };
  StageDynamics current;
  bool current_valid = false;
  /// Work space of the stages, sized once: one stage writes no heap memory of its own.
  StageDynamics stage;
  Eigen::MatrixXd stage_mass;
  Eigen::VectorXd stage_residual, stage_force;

  /// Moves the scratch state to (q, u), realizes its kinematics and fills `out`.
  void calc_stage_dynamics(const Eigen::VectorXd& positions, const Eigen::VectorXd& velocities, StageDynamics& out) {
    write_joint_state(*arm, state, positions, velocities);
    realize_kinematics(*arm, state);
    stage_force.setZero(positions.size());
    JointDynamicsForce::add_passive(*arm, state, stage_force);
    JointDynamicsForce::calc_rigid_mass_matrix(*arm, state, stage_mass);
    stage_mass.diagonal() += arm->parameters.armature;
    out.mass.compute(stage_mass);
    JointDynamicsForce::calc_rigid_residual(*arm, state, Eigen::VectorXd(), stage_residual);
    out.free_force = stage_force - stage_residual;  // passive + g − c
  }

  /// q̈ at (q, u) under the held τ, into `acceleration`.
  void calc_stage_acceleration(const Eigen::VectorXd& positions, const Eigen::VectorXd& velocities, const Eigen::VectorXd& tau,
                               Eigen::VectorXd& acceleration) {
    calc_stage_dynamics(positions, velocities, stage);
    solve_stage(stage, tau, acceleration);
  }

  /// (M + A)⁻¹ (τ + free_force) of `dynamics`, into `acceleration` (LLT::solve's arithmetic, in place).
  void solve_stage(const StageDynamics& dynamics, const Eigen::VectorXd& tau, Eigen::VectorXd& acceleration) const {
    acceleration = tau + dynamics.free_force;
    dynamics.mass.solveInPlace(acceleration);
  }

  /// The stages' vectors of one RK4 step, kept across ticks (sized once).
  struct RungeKuttaScratch {
    Eigen::VectorXd q0, u0, a1, v2, q2, a2, v3, q3, a3, v4, q4, a4;
  };
  RungeKuttaScratch rk;

  /// Whether any joint of `positions` is outside its position limits (where the soft-limit
  /// spring-damper acts: its damping switches on there, a jump no fixed step resolves).
  bool beyond_limits(const Eigen::VectorXd& positions) const {
    if (!options.soft_joint_limits) return false;
    return (positions.array() < arm->parameters.lower.array()).any() || (positions.array() > arm->parameters.upper.array()).any();
  }

  /// Classical fourth-order Runge–Kutta over `duration` in options.steps_per_tick equal steps,
  /// τ held; leaves the state's kinematics realized at the end and qdd under τ there. A tick in
  /// which any stage reaches beyond a joint limit is redone by the adaptive Runge–Kutta–Merson
  /// (at options.accuracy) from the tick's start. Returns false when it fell back.
  bool step_runge_kutta_4(const Eigen::VectorXd& tau, double duration) {
    const double start = state.getTime();
    const int steps = std::max(1, options.steps_per_tick);
    const double h = duration / steps;
    // The tick's start stays in q and qd until the tick is accepted; the stages use rk's buffers.
    RungeKuttaScratch& k = rk;
    Eigen::VectorXd& q0 = k.q0;
    Eigen::VectorXd& u0 = k.u0;
    q0 = q;
    u0 = qd;
    for (int s = 0; s < steps; ++s) {
      if (!current_valid) calc_stage_dynamics(q0, u0, current);
      solve_stage(current, tau, k.a1);
      k.v2 = u0 + 0.5 * h * k.a1;
      k.q2 = q0 + 0.5 * h * u0;
      calc_stage_acceleration(k.q2, k.v2, tau, k.a2);
      k.v3 = u0 + 0.5 * h * k.a2;
      k.q3 = q0 + 0.5 * h * k.v2;
      calc_stage_acceleration(k.q3, k.v3, tau, k.a3);
      k.v4 = u0 + h * k.a3;
      k.q4 = q0 + h * k.v3;
      calc_stage_acceleration(k.q4, k.v4, tau, k.a4);
      const bool at_limit = beyond_limits(q0) || beyond_limits(k.q2) || beyond_limits(k.q3) || beyond_limits(k.q4);
      q0 += (h / 6.0) * (u0 + 2.0 * k.v2 + 2.0 * k.v3 + k.v4);
      u0 += (h / 6.0) * (k.a1 + 2.0 * k.a2 + 2.0 * k.a3 + k.a4);
      if (at_limit || beyond_limits(q0)) {
        state.setTime(start);
        write_joint_state(*arm, state, q, qd);  // q and qd still hold the tick's start
        current_valid = false;
        return false;
      }
      if (!q0.allFinite() || !u0.allFinite()) {
        current_valid = false;
        throw std::runtime_error("runge_kutta_4: the state became NaN or Inf at t = " + std::to_string(start + (s + 1) * h) + " s");
      }
      state.setTime(s + 1 == steps ? start + duration : start + (s + 1) * h);
      calc_stage_dynamics(q0, u0, current);  // the end state: its q̈, and the next step's first stage
      current_valid = true;
    }
    integrator_steps += steps;
    q = q0;
    qd = u0;
    solve_stage(current, tau, qdd);
    return true;
  }

  void rebuild(double time, const Eigen::VectorXd& positions, const Eigen::VectorXd& velocities) {
    const Eigen::VectorXd torque = arm ? arm->held_torque : Eigen::VectorXd();
    arm = make_arm_system(*model, options);
    if (torque.size() == arm->held_torque.size()) arm->held_torque = torque;
    state = arm->system.getDefaultState();
    state.setTime(time);
    write_joint_state(*arm, state, positions, velocities);
    integrator = make_integrator(arm->system, options);
    refresh();
  }

  void refresh() {
    current_valid = false;
    arm->system.realize(state, SimTK::Stage::Acceleration);
    q = read_mobilities(*arm, state.getQ());
    qd = read_mobilities(*arm, state.getU());
    qdd = read_mobilities(*arm, state.getUDot());
  }
};

ArmSimulation::ArmSimulation(const ArmModel& model, const ArmSimulationOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->model = &model;
  impl_->options = options;
  impl_->arm = make_arm_system(model, impl_->options);
  Eigen::VectorXd start(impl_->arm->active_joint_indices.size());
  for (int j = 0; j < start.size(); ++j) start[j] = model.joints[impl_->arm->active_joint_indices[j]].start_position;
  impl_->rebuild(0.0, start, Eigen::VectorXd::Zero(start.size()));
}

ArmSimulation::~ArmSimulation() = default;
ArmSimulation::ArmSimulation(ArmSimulation&&) noexcept = default;
ArmSimulation& ArmSimulation::operator=(ArmSimulation&&) noexcept = default;

int ArmSimulation::dof() const { return static_cast<int>(impl_->arm->active_bodies.size()); }
const std::vector<int>& ArmSimulation::active_joint_indices() const { return impl_->arm->active_joint_indices; }

void ArmSimulation::set_state(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  impl_->state.setTime(time);
  write_joint_state(*impl_->arm, impl_->state, q, qd);
  impl_->refresh();
}

constexpr int kMaxIntegratorStepsPerTick = 20000;

void ArmSimulation::step(const Eigen::VectorXd& tau, double duration) {
  Impl& impl = *impl_;
  if (tau.size() != dof()) {
    throw std::invalid_argument("expected " + std::to_string(dof()) + " joint torques, got " + std::to_string(tau.size()));
  }
  if (!(duration > 0.0)) throw std::invalid_argument("step duration must be positive");
  impl.arm->held_torque = tau;
  if (impl.options.integrator == IntegratorKind::runge_kutta_4 && impl.step_runge_kutta_4(tau, duration)) return;
  impl.state.invalidateAllCacheAtOrAbove(SimTK::Stage::Dynamics);  // forces read the new torque
  // The held torque changes discontinuously at the tick: restart the integrator from the
  // current state (the force element reads the new torque).
  impl.integrator->initialize(impl.state);
  const double end = impl.state.getTime() + duration;
  // A diverging or pathologically stiff state makes adaptive integrators shrink their step
  // without bound; cap the work per tick so that a bad job fails instead of hanging.
  impl.integrator->setInternalStepLimit(kMaxIntegratorStepsPerTick);
  while (true) {
    const SimTK::Integrator::SuccessfulStepStatus status = impl.integrator->stepTo(end);
    if (status == SimTK::Integrator::ReachedReportTime || status == SimTK::Integrator::EndOfSimulation ||
        impl.integrator->getTime() >= end) {
      break;
    }
    if (status == SimTK::Integrator::ReachedStepLimit) {
      throw std::runtime_error("integrator took more than " + std::to_string(kMaxIntegratorStepsPerTick) +
                               " steps in one control tick at t = " + std::to_string(impl.integrator->getTime()) +
                               " s (the state is diverging or too stiff)");
    }
  }
  impl.integrator_steps += impl.integrator->getNumStepsTaken();
  impl.state = impl.integrator->getState();
  impl.refresh();
}

double ArmSimulation::time() const { return impl_->state.getTime(); }
const Eigen::VectorXd& ArmSimulation::q() const { return impl_->q; }
const Eigen::VectorXd& ArmSimulation::qd() const { return impl_->qd; }
const Eigen::VectorXd& ArmSimulation::qdd() const { return impl_->qdd; }

void ArmSimulation::set_payload(const Payload& payload) {
  impl_->options.payload = payload;
  impl_->rebuild(time(), impl_->q, impl_->qd);
}

void ArmSimulation::set_friction_override(const JointFrictionOverride& friction) {
  impl_->options.friction_override = friction;
  impl_->rebuild(time(), impl_->q, impl_->qd);
}

double ArmSimulation::calc_energy() const {
  const ArmSystem& arm = *impl_->arm;
  const SimTK::State& state = impl_->state;
  double energy = arm.matter.calcKineticEnergy(state);
  energy += 0.5 * impl_->qd.dot(arm.parameters.armature.cwiseProduct(impl_->qd));
  for (SimTK::MobilizedBodyIndex b(1); b < arm.matter.getNumBodies(); ++b) {
    const SimTK::MobilizedBody& body = arm.matter.getMobilizedBody(b);
    const SimTK::MassProperties& mass = body.getBodyMassProperties(state);
    energy -= mass.getMass() * SimTK::dot(arm.gravity, body.findStationLocationInGround(state, mass.getMassCenter()));
  }
  return energy;
}

long ArmSimulation::integrator_steps() const {
  return impl_->integrator_steps;
}

// ---------------------------------------------------------------------------------------------
struct ArmDynamics::Impl {
  const ArmModel* model = nullptr;
  ArmSimulationOptions options;  ///< nominal: no payload, no friction override, no limits
  std::unique_ptr<ArmSystem> arm;
  SimTK::State state;

  /// Moves the state to (q, q̇) and realizes its position kinematics, and its velocity
  /// kinematics when `velocities` (what Stage::Position and Stage::Velocity computed for these calls).
  void set(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, bool velocities) {
    write_joint_state(*arm, state, q, qd);
    if (velocities) {
      realize_kinematics(*arm, state);
    } else {
      arm->matter.realizePositionKinematics(state);
    }
  }
};

ArmDynamics::ArmDynamics(const ArmModel& model, std::vector<int> active_joints, const Payload& payload)
    : impl_(std::make_unique<Impl>()) {
  impl_->model = &model;
  impl_->options.active_joints = std::move(active_joints);
  impl_->options.payload = payload;
  impl_->options.soft_joint_limits = false;
  impl_->arm = make_arm_system(model, impl_->options);
  impl_->state = impl_->arm->system.getDefaultState();
  // Kinematics is realized per call (Impl::set); it needs the instance stage (masses, frames) once.
  impl_->arm->system.realize(impl_->state, SimTK::Stage::Instance);
}

ArmDynamics::~ArmDynamics() = default;
ArmDynamics::ArmDynamics(ArmDynamics&&) noexcept = default;
ArmDynamics& ArmDynamics::operator=(ArmDynamics&&) noexcept = default;

int ArmDynamics::dof() const { return static_cast<int>(impl_->arm->active_bodies.size()); }
const ArmModel& ArmDynamics::model() const { return *impl_->model; }
const std::vector<int>& ArmDynamics::active_joint_indices() const { return impl_->arm->active_joint_indices; }

Eigen::VectorXd ArmDynamics::calc_inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                   const Eigen::VectorXd& qdd) {
  if (qdd.size() != dof()) throw std::invalid_argument("expected " + std::to_string(dof()) + " joint accelerations");
  impl_->set(q, qd, true);
  const ArmSystem& arm = *impl_->arm;
  return JointDynamicsForce::calc_rigid_residual(arm, impl_->state, qdd) + arm.parameters.armature.cwiseProduct(qdd);
}

Eigen::VectorXd ArmDynamics::calc_forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                   const Eigen::VectorXd& tau) {
  if (tau.size() != dof()) throw std::invalid_argument("expected " + std::to_string(dof()) + " joint torques");
  impl_->set(q, qd, true);
  const ArmSystem& arm = *impl_->arm;
  const Eigen::VectorXd total = tau + JointDynamicsForce::calc_gravity_generalized_force(arm, impl_->state);
  return JointDynamicsForce::calc_armature_acceleration(arm, impl_->state, total);
}

Eigen::MatrixXd ArmDynamics::calc_mass_matrix(const Eigen::VectorXd& q) {
  impl_->set(q, Eigen::VectorXd::Zero(dof()), false);
  Eigen::MatrixXd mass = JointDynamicsForce::calc_rigid_mass_matrix(*impl_->arm, impl_->state);
  mass.diagonal() += impl_->arm->parameters.armature;
  return mass;
}

Eigen::Vector3d ArmDynamics::calc_point_position(const Eigen::VectorXd& q, int link, const Eigen::Vector3d& offset) {
  impl_->set(q, Eigen::VectorXd::Zero(dof()), false);
  const SimTK::MobilizedBodyIndex body = impl_->arm->link_bodies.at(link);
  const SimTK::Vec3 p = impl_->arm->matter.getMobilizedBody(body).findStationLocationInGround(impl_->state, to_simtk(offset));
  return Eigen::Vector3d(p[0], p[1], p[2]);
}

Eigen::Vector3d ArmDynamics::calc_end_effector_position(const Eigen::VectorXd& q) {
  return calc_point_position(q, impl_->model->end_effector.link, impl_->model->end_effector.offset);
}

Eigen::Matrix3Xd ArmDynamics::calc_point_jacobian(const Eigen::VectorXd& q, int link, const Eigen::Vector3d& offset) {
  impl_->set(q, Eigen::VectorXd::Zero(dof()), false);
  const ArmSystem& arm = *impl_->arm;
  SimTK::Matrix jacobian;  // 3 × nu
  arm.matter.calcStationJacobian(impl_->state, arm.link_bodies.at(link), to_simtk(offset), jacobian);
  Eigen::Matrix3Xd result(3, dof());
  for (int j = 0; j < dof(); ++j)
    for (int r = 0; r < 3; ++r) result(r, j) = jacobian(r, arm.mobility_of_active[j]);
  return result;
}

Eigen::Matrix3Xd ArmDynamics::calc_end_effector_jacobian(const Eigen::VectorXd& q) {
  return calc_point_jacobian(q, impl_->model->end_effector.link, impl_->model->end_effector.offset);
}

namespace {
Eigen::VectorXd collect(const ArmModel& model, const std::vector<int>& joints, double Joint::*field) {
  Eigen::VectorXd values(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) values[j] = model.joints[joints[j]].*field;
  return values;
}
}  // namespace

Eigen::VectorXd ArmDynamics::start_positions() const {
  return collect(*impl_->model, impl_->arm->active_joint_indices, &Joint::start_position);
}
Eigen::VectorXd ArmDynamics::lower_limits() const { return impl_->arm->parameters.lower; }
Eigen::VectorXd ArmDynamics::upper_limits() const { return impl_->arm->parameters.upper; }
Eigen::VectorXd ArmDynamics::effort_limits() const {
  return collect(*impl_->model, impl_->arm->active_joint_indices, &Joint::effort_limit);
}
Eigen::VectorXd ArmDynamics::velocity_limits() const {
  return collect(*impl_->model, impl_->arm->active_joint_indices, &Joint::velocity_limit);
}
Eigen::VectorXd ArmDynamics::viscous_damping() const { return impl_->arm->parameters.viscous; }
Eigen::VectorXd ArmDynamics::coulomb_friction() const { return impl_->arm->parameters.coulomb; }

}  // namespace armfarm
