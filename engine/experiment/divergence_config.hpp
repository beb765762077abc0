#pragma once
// When a job is declared diverged, and its key table (engine/config/config_key.hpp).
#include "engine/config/config_key.hpp"

#include <vector>

namespace armfarm {

struct DivergenceConfig {
  double max_tracking_error = 1.0;     ///< rad, on any joint ...
  double max_error_duration = 0.5;     ///< s, ... for longer than this
  double velocity_limit_factor = 1.5;  ///< |q̇| above this × the model's velocity limit (a runaway, not a fast move)
};

const std::vector<ConfigKey<DivergenceConfig>>& divergence_config_keys();

}  // namespace armfarm
