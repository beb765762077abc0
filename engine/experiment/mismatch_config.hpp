#pragma once
// Model mismatch of a job: how the simulated plant differs from the nominal model the analytic
// feed-forward uses, and its key table (engine/config/config_key.hpp). Units: SI.
#include "engine/config/config_key.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Core>

#include <vector>

namespace armfarm {

struct MismatchConfig {
  Payload payload;               ///< at the end effector
  Eigen::VectorXd viscous;       ///< N·m·s/rad, replaces the model's damping (empty: the model's)
  Eigen::VectorXd coulomb;       ///< N·m, replaces the model's friction (empty: the model's)
  double start_time = 0.0;       ///< s into the evaluation run at which the mismatch appears
};

const std::vector<ConfigKey<MismatchConfig>>& mismatch_config_keys();

}  // namespace armfarm
