#pragma once
// Reading a JSON file (sweep spec, include, `armfarm job` configuration) so that every problem
// names the file, the line and column, and the JSON path: syntax errors, numbers a double
// cannot hold (1e309), and the position of any value for later messages.
#include "base/json_syntax_error.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

namespace armfarm {

/// A parsed JSON text with the position of every value. Paths are written the way spec errors
/// write them: `base.control.kp[0]`, keys that hold a dot quoted (`sweep.grid["control.kp"][1]`).
/// Positions are kept as a tree of path segments (each value: its parent, its own segment such
/// as `.kp` or `[3]`, its offset), so memory and time stay linear in the document's size however
/// deep or long its keys are; a whole path is rebuilt only when a message asks for it.
struct JsonDocument {
  struct Node {
    static constexpr std::size_t kNotAnElement = static_cast<std::size_t>(-1);
    std::size_t parent;   ///< index into nodes; the root's parent is itself (index 0)
    std::string segment;  ///< `key`, `.key` or `["a.b"]` for an object's value; "" for the root and array elements
    std::size_t element = kNotAnElement;  ///< an array element's index (its segment `[3]` is built when asked)
    std::size_t offset = 0;  ///< byte offset of the value's first character
    std::size_t hash = 0;    ///< of the whole path, built segment by segment
  };
  nlohmann::json value;
  std::string text;
  std::vector<Node> nodes;
  std::unordered_multimap<std::size_t, std::size_t> by_hash;  ///< path hash → node index

  /// "line L, column C" (1-based) of the value at `path`, or "" when the document has no such value.
  std::string describe_position(const std::string& path) const;
  /// The whole path of node `index` (`base.control.kp[0]`).
  std::string make_path(std::size_t index) const;
};

/// The deepest nesting of arrays and objects a document may have; deeper is refused.
inline constexpr std::size_t kMaxJsonDepth = 256;

// describe_text_position(text, offset): "line L, column C" of byte `offset` (base/json_syntax_error.hpp).

/// Parses `text` (named `file` in messages). Throws SpecError with one line
/// "FILE: line L, column C: PATH: what" for invalid JSON, numbers out of a double's range,
/// nesting deeper than kMaxJsonDepth, a key given twice in one object, and strings holding a
/// control character (U+0000–U+001F, U+007F: a name or value must print as itself on one line).
JsonDocument parse_json_document(const std::string& text, const std::string& file);

/// Reads the JSON file `path` through the confined reader (engine/io/input_file.hpp: a regular
/// file under the size cap) and parses it as parse_json_document does, so that a syntax error
/// names the file, the line and the column. Throws SpecError or the reader's error.
nlohmann::json read_json_file(const std::string& path);

/// True for strings that spell a non-finite number ("NaN", "inf", "-Infinity", …, any case).
bool is_non_finite_number_text(const std::string& text);

}  // namespace armfarm
