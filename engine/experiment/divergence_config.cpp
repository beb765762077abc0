#include "engine/experiment/divergence_config.hpp"

namespace armfarm {

const std::vector<ConfigKey<DivergenceConfig>>& divergence_config_keys() {
  using C = DivergenceConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"max_tracking_error", "rad", left_open(0.0, 100.0), ListSize::any, "diverged when any joint is off by more than this ...",
       [](C& c) { return make_field(c.max_tracking_error); }},
      {"max_error_duration", "s", closed(0.0, 86400.0), ListSize::any, "... for longer than this",
       [](C& c) { return make_field(c.max_error_duration); }},
      {"velocity_limit_factor", "", left_open(0.0, 100.0), ListSize::any,
       "diverged when a joint exceeds this × its velocity limit (a runaway, figure 4.4)",
       [](C& c) { return make_field(c.velocity_limit_factor); }},
  };
  return keys;
}

}  // namespace armfarm
