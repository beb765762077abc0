#include "engine/io/message_text.hpp"

#include <algorithm>

namespace armfarm {
namespace {

// `line` cut to at most `max_bytes` at a UTF-8 boundary, with the count of bytes left out.
std::string cap_one_line(std::string_view line, std::size_t max_bytes) {
  if (line.size() <= max_bytes) return std::string(line);
  std::size_t cut = max_bytes;
  // Step back over continuation bytes (10xxxxxx) so no character is split.
  while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
  return std::string(line.substr(0, cut)) + " … (" + std::to_string(line.size() - cut) + " more bytes)";
}

}  // namespace

std::string join_shortened(const std::vector<std::string>& items, std::string_view separator, std::size_t shown) {
  std::string text;
  const std::size_t listed = std::min(items.size(), shown);
  for (std::size_t i = 0; i < listed; ++i) {
    if (i > 0) text += separator;
    text += items[i];
  }
  if (items.size() > listed) text += " … and " + std::to_string(items.size() - listed) + " more";
  return text;
}

std::string cap_message_line(std::string_view text, std::size_t max_bytes) {
  std::string capped;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find('\n', start);
    capped += cap_one_line(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start), max_bytes);
    if (end == std::string_view::npos) break;
    capped += '\n';
    start = end + 1;
  }
  return capped;
}

}  // namespace armfarm
