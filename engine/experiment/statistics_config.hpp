#pragma once
// What a control pass's statistics cover beyond the whole pass (pass_statistics.hpp): a window of
// trajectory points for the window_tracking_* metrics (table 6.3 of the thesis scores points
// 325-750 of the figure-eight, after the start-up transient), and its key table
// (engine/config/config_key.hpp).
#include "engine/config/config_key.hpp"

#include <vector>

namespace armfarm {

/// Where the points of statistics.window are counted from.
enum class WindowCounting {
  segment,  ///< from the first point of each loop or reach: the window repeats in every segment
  pass,     ///< from the first point of the pass: one window over the whole trajectory
};
const EnumNames& window_counting_names();

/// A trajectory point is one control tick (one sample of the desired trajectory).
struct StatisticsConfig {
  /// [first, last]: 1-based, inclusive trajectory point numbers as a user counts them (the
  /// thesis's "points 325 to 750" is [325, 750]); empty = no window metrics.
  std::vector<int> window;
  WindowCounting window_counting = WindowCounting::segment;
};

const std::vector<ConfigKey<StatisticsConfig>>& statistics_config_keys();

/// "" when `config` is consistent, else the problem (the window has not 0 or 2 entries, or
/// first > last), for the key statistics.window.
std::string check_statistics_config(const StatisticsConfig& config);

}  // namespace armfarm
