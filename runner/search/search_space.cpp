#include "runner/search/search_space.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace armfarm::search {

const char* to_string(AxisKind kind) {
  switch (kind) {
    case AxisKind::uniform: return "uniform";
    case AxisKind::log_uniform: return "log_uniform";
    case AxisKind::integer: return "integer";
    case AxisKind::categorical: return "categorical";
  }
  return "?";
}

InternalInterval calc_internal_interval(const SearchAxis& axis) {
  switch (axis.kind) {
    case AxisKind::log_uniform: return {std::log(axis.low), std::log(axis.high)};
    case AxisKind::integer: return {axis.low - 0.5, axis.high + 0.5};
    case AxisKind::uniform:
    case AxisKind::categorical: break;
  }
  return {axis.low, axis.high};
}

double calc_internal_coordinate(const SearchAxis& axis, double value) {
  return axis.kind == AxisKind::log_uniform ? std::log(value) : value;
}

double calc_axis_value(const SearchAxis& axis, double internal) {
  double value = internal;
  if (axis.kind == AxisKind::log_uniform) value = std::exp(internal);
  if (axis.kind == AxisKind::integer) value = std::nearbyint(internal);
  return std::clamp(value, axis.low, axis.high);
}

SearchPoint calc_random_point(const SearchSpace& space, RandomStream& stream) {
  SearchPoint point;
  point.reserve(space.axes.size());
  for (const SearchAxis& axis : space.axes) {
    if (axis.kind == AxisKind::categorical) {
      point.push_back(static_cast<double>(stream.uniform_index(axis.choice_count)));
      continue;
    }
    const InternalInterval interval = calc_internal_interval(axis);
    point.push_back(calc_axis_value(axis, stream.uniform(interval.low, interval.high)));
  }
  return point;
}

RandomStream make_trial_stream(std::uint64_t seed, std::size_t trial) {
  return RandomStream(seed, "search.trial." + std::to_string(trial));
}

}  // namespace armfarm::search
