#include "engine/physics/simulation_config.hpp"

namespace armfarm {

const EnumNames& integrator_kind_names() {
  static const EnumNames names = {
      {"runge_kutta_merson", static_cast<int>(IntegratorKind::runge_kutta_merson), "adaptive 4th/5th order, restarted every tick"},
      {"runge_kutta_3", static_cast<int>(IntegratorKind::runge_kutta_3), "adaptive 2nd/3rd order"},
      {"runge_kutta_feldberg", static_cast<int>(IntegratorKind::runge_kutta_feldberg), "adaptive 4th/5th order"},
      {"explicit_euler", static_cast<int>(IntegratorKind::explicit_euler), "adaptive 1st order"},
      {"semi_explicit_euler2", static_cast<int>(IntegratorKind::semi_explicit_euler2), "semi-explicit Euler with error estimate"},
      {"verlet", static_cast<int>(IntegratorKind::verlet), "adaptive Verlet"},
      {"cpodes", static_cast<int>(IntegratorKind::cpodes), "implicit multistep (CPODES)"},
      {"runge_kutta_4", static_cast<int>(IntegratorKind::runge_kutta_4),
       "fixed-step classical 4th order (the default), integrator_steps_per_tick steps per tick; ticks at a joint limit go to runge_kutta_merson"},
  };
  return names;
}

const std::vector<ConfigKey<SimulationConfig>>& simulation_config_keys() {
  using C = SimulationConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"dt", "s", closed(1e-4, 0.1), ListSize::any, "control and learning period (the thesis's TAU); torques are held over a tick",
       [](C& c) { return make_field(c.dt); }},
      {"integrator", "", {}, ListSize::any, "how the plant is integrated over a tick (engine/README.md: the accuracy criterion and measurements behind the default)",
       [](C& c) { return make_choice_field(c.integrator, integrator_kind_names()); }},
      {"integrator_accuracy", "", closed(1e-12, 0.1), ListSize::any, "relative accuracy of the adaptive integrators (and of runge_kutta_4 at a joint limit)",
       [](C& c) { return make_field(c.integrator_accuracy); }},
      {"integrator_steps_per_tick", "", closed(1, 1000), ListSize::any,
       "equal steps of the fixed-step runge_kutta_4 per PD period (per tick when pd_substeps is 1); \"auto\" = the fewest the step-stability criterion calls stable (engine/README.md)",
       [](C& c) { return make_field(c.integrator_steps_per_tick); }},
      {"pd_substeps", "", closed(1, 100), ListSize::any,
       "PD loop runs per tick (period dt / pd_substeps; feed-forward, learning and statistics stay at dt); 1 = the thesis's single loop; \"auto\" = the fewest the step-stability criterion calls stable for the job's gains (engine/README.md)",
       [](C& c) { return make_field(c.pd_substeps); }},
      {"armature_scale", "", closed(0.0, 10.0), ListSize::any,
       "multiplies the model's joint armature (plant and nominal model); 0 = none, as the thesis's arm",
       [](C& c) { return make_field(c.armature_scale); }},
  };
  return keys;
}

}  // namespace armfarm
