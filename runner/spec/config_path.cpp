#include "runner/spec/config_path.hpp"

#include "base/did_you_mean.hpp"

#include <vector>

namespace armfarm {

const nlohmann::json* find_config_element(const nlohmann::json& config, const ConfigPath& path, std::string& problem) {
  const nlohmann::json* node = &config;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const PathSegment& segment = path[i];
    const std::string parent = i == 0 ? std::string("the configuration") : "'" + path.to_string(i) + "'";
    if (segment.index) {
      if (!node->is_array()) {
        problem = parent + " is not an array";
        return nullptr;
      }
      if (*segment.index >= node->size()) {
        problem = "index " + std::to_string(*segment.index) + " is out of range: " + parent + " has " +
                  std::to_string(node->size()) + " elements";
        return nullptr;
      }
      node = &(*node)[*segment.index];
    } else {
      if (!node->is_object()) {
        problem = parent + " is not an object";
        return nullptr;
      }
      const auto found = node->find(segment.key);
      if (found == node->end()) {
        std::vector<std::string> keys;
        for (const auto& item : node->items()) keys.push_back(item.key());
        problem = "no key '" + segment.key + "' in " + parent + make_did_you_mean(segment.key, keys);
        return nullptr;
      }
      node = &*found;
    }
  }
  return node;
}

void set_config_element(nlohmann::json& config, const ConfigPath& path, nlohmann::json value) {
  nlohmann::json* node = &config;
  for (const PathSegment& segment : path) node = segment.index ? &node->at(*segment.index) : &node->at(segment.key);
  *node = std::move(value);
}

}  // namespace armfarm
