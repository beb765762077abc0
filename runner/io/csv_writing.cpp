#include "runner/io/csv_writing.hpp"

#include <charconv>
#include <cmath>

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

std::string make_shortest_number_text(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  const std::to_chars_result result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

std::string make_csv_value_field(const nlohmann::json& value) {
  if (value.is_number_integer()) return value.dump();
  if (value.is_number_float()) return make_shortest_number_text(value.get<double>());
  if (value.is_string()) return make_csv_field(value.get<std::string>());
  if (value.is_null()) return "";
  return make_csv_field(value.dump());
}

}  // namespace armfarm
