#include "runner/execution/job_cost_estimate.hpp"

#include <string>

namespace armfarm {
namespace {

// The number at a dotted path of `config`, or `fallback` where there is none.
double find_number(const nlohmann::json& config, const std::string& dotted, double fallback) {
  const nlohmann::json* node = &config;
  std::size_t begin = 0;
  while (begin <= dotted.size()) {
    const std::size_t end = dotted.find('.', begin);
    const std::string name = dotted.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
    if (!node->is_object() || !node->contains(name)) return fallback;
    node = &(*node)[name];
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return node->is_number() ? node->get<double>() : fallback;
}

}  // namespace

double estimate_job_cost(const nlohmann::json& config) {
  if (!config.is_object()) return 1.0;
  if (config.contains("fake")) {
    const double cost = find_number(config, "fake.sleep_ms", 0.0) + find_number(config, "fake.work", 0.0) / 1e4;
    return cost > 0.0 ? cost : 1.0;
  }
  const auto kind_node = config.find("trajectory");
  if (kind_node == config.end() || !kind_node->is_object() || !kind_node->contains("kind") ||
      !(*kind_node)["kind"].is_string()) {
    return 1.0;
  }
  const std::string kind = (*kind_node)["kind"].get<std::string>();
  const double dt = find_number(config, "dt", 0.01);
  double ticks = 1.0;
  if (kind == "sine") {
    ticks = find_number(config, "trajectory.sine.duration", 20.0) / (dt > 0.0 ? dt : 0.01);
  } else if (kind == "figure_eight") {
    ticks = find_number(config, "trajectory.figure_eight.points_per_loop", 750.0) *
            find_number(config, "trajectory.figure_eight.loops", 3.0);
  } else if (kind == "reaching") {
    ticks = find_number(config, "trajectory.reaching.points_per_reach", 100.0) *
            find_number(config, "trajectory.reaching.reaches", 20.0);
  } else if (kind == "recorded") {
    ticks = 1000.0 * find_number(config, "trajectory.recorded.loops", 1.0);
  }
  double passes = 1.0;
  const auto learning = config.find("learning");
  if (learning != config.end() && learning->is_object()) {
    if (learning->value("mode", std::string()) == "batch") passes += find_number(config, "learning.collect_repeats", 2.0);
    if (learning->value("heldout", false)) passes *= 2.0;
  }
  const double cost = ticks * passes;
  return cost > 0.0 ? cost : 1.0;
}

}  // namespace armfarm
