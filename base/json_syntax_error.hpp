#pragma once
// Where a text file has a problem ("line L, column C"), and a JSON parser's syntax error as
// armfarm words it: "line L, column C: not valid JSON: REASON". The one home of both for every
// JSON file armfarm reads: sweep specs, includes and configurations (runner/spec/json_document.cpp)
// and the thesis results (analysis/thesis_comparison.cpp), which parse with different rules and
// so cannot share one parser. Standard library only (base/README.md): callers pass what
// nlohmann::json's parse_error gives, its byte count and its what().
#include <cstddef>
#include <string>

namespace armfarm {

/// "line L, column C" (1-based) of byte `offset` of `text`.
inline std::string describe_text_position(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

/// The offset of the character a JSON parser stopped at, from its count of bytes read
/// (nlohmann's parse_error::byte counts the offending character too).
inline std::size_t calc_json_syntax_error_offset(std::size_t bytes_read) { return bytes_read > 0 ? bytes_read - 1 : 0; }

/// "not valid JSON: REASON" from nlohmann's parse_error message, which is
/// "[json.exception.parse_error.101] parse error at line 1, column 5: REASON; last read: 'tru'"
/// ("column" is nlohmann's, the REASON its lexer's). The library gives the reason only inside
/// that text, so this is the one place that takes it out: after the ": " that follows "column",
/// without the "; last read: ..." tail, so that a file that is not JSON at all (an include naming
/// /etc/passwd) never has its bytes printed; the line and column suffice.
inline std::string make_json_syntax_reason(const std::string& parser_message) {
  std::string reason = parser_message;
  const std::size_t colon = reason.find(": ", reason.find("column"));
  if (colon != std::string::npos) reason = reason.substr(colon + 2);
  const std::size_t last_read = reason.find("; last read:");
  if (last_read != std::string::npos) reason.erase(last_read);
  return "not valid JSON: " + reason;
}

}  // namespace armfarm
