#include "analysis/printable_text.hpp"

#include <cstddef>
#include <cstring>

namespace armfarm {

namespace {

constexpr const char* kReplacement = "\xEF\xBF\xBD";  // U+FFFD

/// The length of the well-formed UTF-8 sequence at `text[at]` (RFC 3629: no overlong forms, no
/// surrogates, at most U+10FFFF), or 0 when there is none.
std::size_t utf8_sequence_length(const std::string& text, std::size_t at) {
  const auto byte = [&text](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(at);
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the allowed range of the second byte
  if (lead < 0x80) return 1;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  if (byte(at + 1) < low || byte(at + 1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i) {
    if (byte(at + i) < 0x80 || byte(at + i) > 0xBF) return 0;
  }
  return length;
}

// U+2400 + c for a C0 control c, U+2421 for DEL (the Control Pictures block), as UTF-8.
std::string make_control_picture(unsigned char c) {
  const unsigned code = c == 0x7F ? 0x2421u : 0x2400u + c;
  return {static_cast<char>(0xE0 | (code >> 12)), static_cast<char>(0x80 | ((code >> 6) & 0x3F)),
          static_cast<char>(0x80 | (code & 0x3F))};
}

// The text with each unprintable character replaced: a C0 control or DEL by `c0(byte)`, and
// a C1 control or a byte that is not UTF-8 by U+FFFD; `keep` C0 characters stay.
template <typename C0Replacement>
std::string replace_unprintable(const std::string& text, const char* keep, const C0Replacement& c0) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t at = 0; at < text.size();) {
    const auto lead = static_cast<unsigned char>(text[at]);
    const std::size_t length = utf8_sequence_length(text, at);
    if (length == 0) {
      out += kReplacement;
      ++at;
      continue;
    }
    const bool kept = lead != 0 && std::strchr(keep, lead) != nullptr;
    const bool c0_or_del = length == 1 && (lead < 0x20 || lead == 0x7F) && !kept;
    const bool c1 = length == 2 && lead == 0xC2 && static_cast<unsigned char>(text[at + 1]) < 0xA0;
    if (c0_or_del) {
      out += c0(lead);
    } else if (c1) {
      out += kReplacement;
    } else {
      out.append(text, at, length);
    }
    at += length;
  }
  return out;
}

}  // namespace

std::string make_printable_text(const std::string& text, bool keep_newlines) {
  return replace_unprintable(text, keep_newlines ? "\n" : "", [](unsigned char) { return std::string(kReplacement); });
}

std::string make_visible_text(const std::string& text) { return replace_unprintable(text, "\n\t", make_control_picture); }

}  // namespace armfarm
