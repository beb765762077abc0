#include "engine/experiment/statistics_config.hpp"

#include <string>

namespace armfarm {

const EnumNames& window_counting_names() {
  static const EnumNames names = {
      {"segment", static_cast<int>(WindowCounting::segment), "points counted from each loop's or reach's first point"},
      {"pass", static_cast<int>(WindowCounting::pass), "points counted from the pass's first point"},
  };
  return names;
}

const std::vector<ConfigKey<StatisticsConfig>>& statistics_config_keys() {
  using C = StatisticsConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"window", "", closed(1, 1e9), ListSize::any,
       "[first, last] trajectory points, first <= last (1-based, inclusive; one point per control tick) scored by the "
       "window_tracking_* metrics; [] = none",
       [](C& c) { return make_field(c.window); }},
      {"window_counting", "", {}, ListSize::any,
       "where window's points are counted from: segment (each loop or reach, the window repeats) or pass (the whole pass)",
       [](C& c) { return make_choice_field(c.window_counting, window_counting_names()); }},
  };
  return keys;
}

std::string check_statistics_config(const StatisticsConfig& config) {
  const std::vector<int>& window = config.window;
  if (window.empty()) return {};
  if (window.size() != 2) {
    return "has " + std::to_string(window.size()) + (window.size() == 1 ? " value" : " values") +
           "; give [] (no window) or [first, last]";
  }
  if (window[0] > window[1]) {
    return "first point " + std::to_string(window[0]) + " is after last point " + std::to_string(window[1]);
  }
  return {};
}

}  // namespace armfarm
