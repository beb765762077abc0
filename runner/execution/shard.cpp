#include "runner/execution/shard.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace armfarm {

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  Shard shard;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    std::size_t used_index = 0, used_count = 0;
    shard.index = std::stoi(text.substr(0, slash), &used_index);
    shard.count = std::stoi(text.substr(slash + 1), &used_count);
    if (used_index != slash || used_count != text.size() - slash - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("--shard " + text + ": expected I/N, e.g. 2/4");
  }
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count) {
    throw std::invalid_argument("--shard " + text + ": needs 1 <= I <= N");
  }
  return shard;
}

std::vector<int> calc_shard_assignment(const std::vector<std::string>& keys, const std::vector<double>& costs,
                                       int count) {
  if (!costs.empty() && costs.size() != keys.size()) {
    throw std::invalid_argument("shard assignment: " + std::to_string(costs.size()) + " costs for " +
                                std::to_string(keys.size()) + " jobs");
  }
  for (double c : costs) {
    if (!(c > 0.0) || !std::isfinite(c)) throw std::invalid_argument("shard assignment: a job cost of " + std::to_string(c));
  }
  std::vector<std::size_t> order(keys.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto cost = [&](std::size_t i) { return costs.empty() ? 1.0 : costs[i]; };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (cost(a) != cost(b)) return cost(a) > cost(b);
    return keys[a] < keys[b];
  });
  std::vector<double> load(static_cast<std::size_t>(std::max(count, 1)), 0.0);
  std::vector<int> shard_of(keys.size(), 1);
  for (std::size_t i : order) {
    const auto least = std::min_element(load.begin(), load.end());  // the first among equals
    *least += cost(i);
    shard_of[i] = static_cast<int>(least - load.begin()) + 1;
  }
  return shard_of;
}

}  // namespace armfarm
