#pragma once
// Writing CSV that any reader takes back exactly: RFC 4180 fields (quoted when they hold a
// comma, a double quote, CR or LF; quotes doubled) and numbers in the shortest form that reads
// back to the same double (base/number_format.hpp: format_shortest_number), so 0.1 prints as
// 0.1, not 0.10000000000000001.
#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// `text` as one RFC 4180 field.
std::string make_csv_field(const std::string& text);

/// A JSON parameter value as a CSV field: integers as integers, other numbers shortest, strings
/// as they are, anything else as compact JSON; quoted as needed.
std::string make_csv_value_field(const nlohmann::json& value);

}  // namespace armfarm
