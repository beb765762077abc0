#pragma once
// Which signals a job records, and its key table (engine/config/config_key.hpp).
#include "engine/config/config_key.hpp"

#include <string>
#include <vector>

namespace armfarm {

struct RecordingConfig {
  /// Names from recordable_series_names() (series_recorder.hpp): POS, POS_D, PHI, PHI_D, VEL,
  /// VEL_D, ACC, ACC_D, TOR, F, FF, RF, TRIAL.
  std::vector<std::string> series = {"TRIAL"};
  int every = 1;  ///< keep one sample in `every` control ticks
};

const std::vector<ConfigKey<RecordingConfig>>& recording_config_keys();

}  // namespace armfarm
