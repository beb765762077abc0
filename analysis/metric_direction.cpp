#include "analysis/metric_direction.hpp"

#include <stdexcept>

namespace armfarm {

BetterDirection find_metric_direction(const MetricInfoTable& info, const std::string& name) {
  auto found = info.find(name);
  if (found == info.end()) return BetterDirection::unknown;
  const std::string& word = found->second.direction;
  if (word == "lower") return BetterDirection::lower;
  if (word == "higher") return BetterDirection::higher;
  if (word == "none") return BetterDirection::none;
  return BetterDirection::unknown;
}

bool is_result_metric(const MetricInfoTable& info, const std::string& name) {
  auto found = info.find(name);
  return found == info.end() || found->second.kind == "result";
}

const char* to_string(BetterDirection direction) {
  switch (direction) {
    case BetterDirection::lower: return "lower";
    case BetterDirection::higher: return "higher";
    case BetterDirection::none: return "none";
    case BetterDirection::unknown: return "unknown";
  }
  return "unknown";
}

BetterDirection parse_better_direction(const std::string& word) {
  if (word == "lower") return BetterDirection::lower;
  if (word == "higher") return BetterDirection::higher;
  if (word == "none") return BetterDirection::none;
  throw std::invalid_argument("direction must be lower, higher or none, not '" + word + "'");
}

}  // namespace armfarm
