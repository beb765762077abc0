#pragma once
// Numbers as text, the project's one home for it: the general form that messages, docs and
// outputs print (printf's %g: 6 significant digits for a reader, 17 to read back the same
// double), the form of a table cell, and the shortest text that reads back the same double
// (CSV exports and tables, Slurm scripts). Standard library only, so that every layer may use it
// (base/README.md). printf's conversions and std::to_chars use the C locale's decimal point.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

namespace armfarm {

/// `value` with `significant_digits` significant digits (1 to 17), printf's "%.*g": "0.05",
/// "1e+06", "-1.5", "inf", "nan". 6 is what a reader needs; 17 reads back as the same double.
inline std::string format_number(double value, int significant_digits = 6) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

/// A table cell: `significant_digits` significant digits, in scientific notation ("1.950e-03")
/// when 0 < |value| < 1e-2 or |value| ≥ 1e5, else as "%.*g" ("0.89", "137"); "nan", "inf", "-inf".
inline std::string format_table_number(double value, int significant_digits = 4) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  const double magnitude = std::fabs(value);
  if (value != 0.0 && (magnitude < 1e-2 || magnitude >= 1e5)) {
    std::snprintf(text, sizeof text, "%.*e", significant_digits - 1, value);
  } else {
    std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  }
  return text;
}

/// The shortest decimal text that parses back to `value` exactly (std::to_chars): "0.1", not
/// "0.10000000000000001"; "60", "90.5", "1e-300", "-0"; "nan", "inf", "-inf" for the non-finite
/// (Python's float() and pandas read those).
inline std::string format_shortest_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  const std::to_chars_result end = std::to_chars(text, text + sizeof text, value);
  return std::string(text, end.ptr);
}

}  // namespace armfarm
