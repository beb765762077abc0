#pragma once
// Reading a JSON file (sweep spec, include, `armfarm job` configuration) so that every problem
// names the file, the line and column, and the JSON path: syntax errors, numbers a double
// cannot hold (1e309), and the position of any value for later messages.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <map>
#include <string>

namespace armfarm {

/// A parsed JSON text with the position of every value. Paths are written the way spec errors
/// write them: `base.control.kp[0]`, keys that hold a dot quoted (`sweep.grid["control.kp"][1]`).
struct JsonDocument {
  nlohmann::json value;
  std::string text;
  std::map<std::string, std::size_t> offsets;  ///< JSON path → byte offset of the value's first character

  /// "line L, column C" (1-based) of the value at `path`, or "" when the document has no such value.
  std::string describe_position(const std::string& path) const;
};

/// "line L, column C" of byte `offset` of `text`.
std::string describe_text_position(const std::string& text, std::size_t offset);

/// Parses `text` (named `file` in messages). Throws SpecError with one line
/// "FILE: line L, column C: PATH: what" for invalid JSON and for numbers out of a double's range.
JsonDocument parse_json_document(const std::string& text, const std::string& file);

/// True for strings that spell a non-finite number ("NaN", "inf", "-Infinity", …, any case).
bool is_non_finite_number_text(const std::string& text);

}  // namespace armfarm
