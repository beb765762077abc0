#pragma once
// How a job's plant is stepped: the control period and the Simbody integrator, and their key
// table (engine/config/config_key.hpp). The integrator's defaults are ArmSimulationOptions's
// (one home); dt is the job's control and learning period.
#include "engine/config/config_key.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <vector>

namespace armfarm {

const EnumNames& integrator_kind_names();

struct SimulationConfig {
  double dt = 0.01;  ///< s, control and learning period (the thesis's TAU); torques are held over a tick
  IntegratorKind integrator = ArmSimulationOptions{}.integrator;
  double integrator_accuracy = ArmSimulationOptions{}.accuracy;  ///< relative accuracy of adaptive integrators
};

const std::vector<ConfigKey<SimulationConfig>>& simulation_config_keys();

}  // namespace armfarm
