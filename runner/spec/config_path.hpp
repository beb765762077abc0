#pragma once
// Dotted paths into a job configuration: "learning.lwpr.init_D", "control.kp[1]" (array
// indices are 0-based, as in JSON tools), "trajectory.waypoints[2][0]".
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// One step of a path: an object key or an array index.
struct PathSegment {
  std::string key;                   ///< used when `index` is empty
  std::optional<std::size_t> index;  ///< array element
};

/// Splits a dotted path. Throws std::invalid_argument (message without the path) when malformed.
std::vector<PathSegment> parse_config_path(const std::string& path);

/// The dotted text of the first `count` segments (all of them by default).
std::string make_config_path(const std::vector<PathSegment>& segments, std::size_t count = SIZE_MAX);

/// The element a path names in `config`, or nullptr; on failure `problem` says which step failed
/// and, for a key, suggests the closest existing one.
const nlohmann::json* find_config_element(const nlohmann::json& config, const std::vector<PathSegment>& segments,
                                          std::string& problem);

/// Replaces the element a path names (which must exist, see find_config_element).
void set_config_element(nlohmann::json& config, const std::vector<PathSegment>& segments, nlohmann::json value);

}  // namespace armfarm
