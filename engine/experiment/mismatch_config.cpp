#include "engine/experiment/mismatch_config.hpp"

namespace armfarm {

const std::vector<ConfigKey<MismatchConfig>>& mismatch_config_keys() {
  using C = MismatchConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"payload.mass", "kg", closed(0.0, 100.0), ListSize::any, "a mass at the end effector the nominal model does not know; 0 = none",
       [](C& c) { return make_field(c.payload.mass); }},
      {"payload.offset", "m", closed(-2.0, 2.0), ListSize::any, "its centre of mass in the end-effector link frame",
       [](C& c) { return make_field(c.payload.offset); }},
      {"payload.radius_of_gyration", "m", closed(0.0, 2.0), ListSize::any, "its inertia is mass·r²·I about its centre",
       [](C& c) { return make_field(c.payload.radius_of_gyration); }},
      {"viscous", "N·m·s/rad", closed(0.0, 1e4), ListSize::per_joint, "joint viscous friction replacing the model's; [] = the model's",
       [](C& c) { return make_field(c.viscous); }},
      {"coulomb", "N·m", closed(0.0, 1e4), ListSize::per_joint, "joint Coulomb friction replacing the model's; [] = the model's",
       [](C& c) { return make_field(c.coulomb); }},
      {"start_time", "s", closed(0.0, 86400.0), ListSize::any,
       "time into the evaluation run at which the mismatch appears (0 = from the start, also while collecting)",
       [](C& c) { return make_field(c.start_time); }},
  };
  return keys;
}

}  // namespace armfarm
