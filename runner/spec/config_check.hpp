#pragma once
// Generic checks of configuration values against a JobConfigSchema's defaults: every key must
// exist in the defaults, every value must have the default's JSON type (a float default accepts
// any number; an integer default accepts integral numbers; an empty default array means an
// array of numbers; a null default accepts anything). Values come back normalized to the
// default's type (1 → 1.0 for a float), so equal configurations serialize identically.
#include "runner/spec/config_path.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace armfarm {

/// One problem calc_checked_value found: the value's path as the message prints it
/// ("base.control.kp[0]", an unknown key as written, "(configuration)" for the whole value) and
/// what is wrong there. Readers that locate the problem in a document read `path`, not the line.
struct CheckedValueProblem {
  std::string path;
  std::string problem;
  /// "path: problem", the line a user sees.
  std::string line() const { return path + ": " + problem; }
};

/// Checks `value` against `reference` (the default at `path`), appending its problems to
/// `problems`. Returns the normalized value (meaningless when problems were added).
nlohmann::json calc_checked_value(const nlohmann::json& value, const nlohmann::json& reference, const std::string& path,
                                  std::vector<CheckedValueProblem>& problems);

/// The default that describes the element a path names: object keys descend into the
/// defaults, array indices into the default array's first element (a number for an empty one).
/// Returns nullptr (with `problem` set) when the defaults have no such key.
const nlohmann::json* find_schema_reference(const nlohmann::json& defaults, const ConfigPath& segments,
                                            std::string& problem);

/// Overlays `overrides` onto `target`: objects merge key by key, everything else is replaced.
void merge_config_into(nlohmann::json& target, const nlohmann::json& overrides);

}  // namespace armfarm
