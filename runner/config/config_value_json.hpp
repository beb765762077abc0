#pragma once
// JSON ↔ one configuration field, driven by the engine's key tables
// (engine/config/config_key.hpp): the only place that knows how each ValueKind is spelled in
// JSON. Used by the job configuration (job_config_json.hpp) and LWPR's parameter files
// (runner/config/lwpr_params_json.hpp).
#include "engine/config/config_key.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// The field's value as JSON: numbers, booleans, strings, enum names; lists as arrays;
/// real_or_list and real_matrix as a number when they hold one element.
nlohmann::json make_field_json(const FieldRef& field);

struct FieldReadOptions {
  bool flags_as_numbers = false;        ///< accept 0 and 1 for booleans (the LWPR library's files)
  bool case_insensitive_names = false;  ///< accept "Gaussian" for "gaussian"
};

/// Stores `value` into the field. Returns "" on success, else what is wrong ("expected a
/// number, got \"big\""); `suffix` receives the element of a list at fault ("[2]", "[1][0]").
/// Ranges are not checked here (validate() does, with the model's facts).
std::string read_field_json(const nlohmann::json& value, const FieldRef& field, std::string& suffix,
                            const FieldReadOptions& options = {});

}  // namespace armfarm
