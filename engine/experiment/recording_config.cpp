#include "engine/experiment/recording_config.hpp"

#include "engine/experiment/series_recorder.hpp"

namespace armfarm {

const std::vector<ConfigKey<RecordingConfig>>& recording_config_keys() {
  using C = RecordingConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"series", "", {}, ListSize::any,
       "recorded signals: POS, POS_D (end effector x, y, z), PHI, PHI_D, VEL, VEL_D, ACC, ACC_D (per joint), TOR, F, FF "
       "(applied, feedback, feed-forward torque), RF (receptive fields), TRIAL (one row per loop or reach); heldout_ before a per-tick name (heldout_F) records it in every held-out pass, "
       "stored as heldout_F_c<checkpoint>",
       [](C& c) { return make_field(c.series, &recordable_series_names); }},
      {"every", "", closed(1, 1e6), ListSize::any, "keep one row in this many ticks", [](C& c) { return make_integer_field(c.every); }},
  };
  return keys;
}

}  // namespace armfarm
