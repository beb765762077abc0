#include "runner/io/csv_writing.hpp"

#include "base/number_format.hpp"

namespace armfarm {

std::string make_csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string field = "\"";
  for (const char c : text) {
    if (c == '"') field += '"';
    field += c;
  }
  return field + "\"";
}

std::string make_csv_value_field(const nlohmann::json& value) {
  if (value.is_number_integer()) return value.dump();
  if (value.is_number_float()) return format_shortest_number(value.get<double>());
  if (value.is_string()) return make_csv_field(value.get<std::string>());
  if (value.is_null()) return "";
  return make_csv_field(value.dump());
}

}  // namespace armfarm
