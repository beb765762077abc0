#pragma once
// How a job's plant is stepped: the control period and the Simbody integrator, and their key
// table (engine/config/config_key.hpp). The integrator's defaults are ArmSimulationOptions's
// (one home); dt is the job's control and learning period.
#include "engine/config/config_key.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <optional>
#include <vector>

namespace armfarm {

const EnumNames& integrator_kind_names();

struct SimulationConfig {
  double dt = 0.01;  ///< s, control and learning period (the thesis's TAU); torques are held over a tick
  IntegratorKind integrator = ArmSimulationOptions{}.integrator;
  double integrator_accuracy = ArmSimulationOptions{}.accuracy;  ///< relative accuracy of adaptive integrators
  /// runge_kutta_4: equal steps per PD period (per tick when pd_substeps is 1). Empty ("auto"):
  /// the fewest that the step-stability criterion (engine/control/step_stability.hpp) calls
  /// stable with its margin on this arm, its damping and gains; a value the criterion calls
  /// unstable is refused by validate().
  std::optional<int> integrator_steps_per_tick;
  /// The PD loop runs this many times per tick (period dt / pd_substeps) on the plant's state,
  /// the desired state extrapolated within the tick; the feed-forward, learning and the
  /// statistics stay at dt. The learner's target is the torque averaged over the tick. 1: the
  /// thesis's single 10 ms loop. Empty ("auto"): the fewest the criterion calls stable with its
  /// margin for the job's gains (1 for the default gains on the LWR III; 7 for appendix D's).
  std::optional<int> pd_substeps;
  /// Multiplies every joint's armature (reflected rotor inertia) of the model, in the plant and
  /// in the nominal model alike; 0 removes it (the thesis's simulated arm had none). The default
  /// gains follow, since they are placed on the mass-matrix diagonal with armature.
  double armature_scale = 1.0;
};

const std::vector<ConfigKey<SimulationConfig>>& simulation_config_keys();

}  // namespace armfarm
