#include "engine/io/number_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace armfarm {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Whether `text` is [+|-] digits [. digits] [(e|E) [+|-] digits] with digits beside the point.
bool is_decimal_number(std::string_view text) {
  std::size_t i = 0;
  const std::size_t n = text.size();
  if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < n && is_digit(text[i])) ++i, ++digits;
  if (i < n && text[i] == '.') {
    ++i;
    while (i < n && is_digit(text[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < n && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
    std::size_t exponent_digits = 0;
    while (i < n && is_digit(text[i])) ++i, ++exponent_digits;
    if (exponent_digits == 0) return false;
  }
  return i == n;
}

}  // namespace

std::optional<double> parse_finite_number(std::string_view token) {
  if (!is_decimal_number(token)) return std::nullopt;
  // from_chars takes no leading '+'; the grammar above has checked everything else.
  const std::string_view digits = token[0] == '+' ? token.substr(1) : token;
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<int> parse_integer(std::string_view token) {
  const std::string_view digits = !token.empty() && token[0] == '+' ? token.substr(1) : token;
  if (digits.empty() || (digits[0] == '-' && digits.size() == 1)) return std::nullopt;
  for (std::size_t i = digits[0] == '-' ? 1 : 0; i < digits.size(); ++i) {
    if (!is_digit(digits[i])) return std::nullopt;
  }
  int value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return value;
}

std::string describe_token(std::string_view token) {
  constexpr std::string_view kNumberCharacters = "0123456789+-.eEinfaINFAty";
  bool quotable = !token.empty() && token.size() <= 24;
  for (char c : token) quotable = quotable && kNumberCharacters.find(c) != std::string_view::npos;
  if (quotable) return ": '" + std::string(token) + "'";
  if (token.empty()) return " (empty)";
  return " (a " + std::to_string(token.size()) + "-byte token, not shown)";
}

std::string describe_bad_number(std::string_view token) {
  if (is_decimal_number(token)) {
    // The grammar holds, so the value is out of range: strtod tells which way (0 or a tiny
    // value on underflow, HUGE_VAL on overflow).
    const std::string text(token);
    const double value = std::strtod(text.c_str(), nullptr);
    const std::string quoted = token.size() <= 24 ? "'" + text + "'" : "a " + std::to_string(token.size()) + "-digit number";
    if (std::abs(value) < 1.0) return quoted + " underflows to zero (below 4.9e-324, the smallest double, in magnitude)";
    return quoted + " overflows a double (above 1.8e308 in magnitude)";
  }
  return "not a finite number" + describe_token(token);
}

std::string make_bad_number_ending(std::string_view token) {
  if (is_decimal_number(token)) return ": " + describe_bad_number(token);
  return " is not a finite number" + describe_token(token);
}

std::size_t find_control_character(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) return i;
  }
  return std::string_view::npos;
}

std::string describe_control_character(char c) {
  if (c == '\0') return "NUL";
  if (c == '\r') return "CR";
  char text[32];
  std::snprintf(text, sizeof text, "control character 0x%02x", static_cast<unsigned char>(c));
  return text;
}

}  // namespace armfarm
