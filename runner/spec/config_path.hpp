#pragma once
// Lookups of a typed path (base/config_path.hpp, the one parser) in a job configuration's JSON
// tree: finding an element with a message that says which step failed, and replacing one.
#include "base/config_path.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// The element a path names in `config`, or nullptr; on failure `problem` says which step failed
/// and, for a key, suggests the closest existing one.
const nlohmann::json* find_config_element(const nlohmann::json& config, const ConfigPath& path, std::string& problem);

/// Replaces the element a path names (which must exist, see find_config_element).
void set_config_element(nlohmann::json& config, const ConfigPath& path, nlohmann::json value);

}  // namespace armfarm
