#pragma once
// The CLI's range checks of numeric options, in place of CLI11's Range, PositiveNumber and
// NonNegativeNumber, whose messages print their bounds with std::to_string (the largest double as
// 309 digits). The same descriptions in --help; a message prints its bounds with
// base/number_format.hpp ("Value 300 not in range 1 to 200"). NaN and infinities are refused.
#include "base/number_format.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace armfarm::cli {

/// Whether `input` reads as a finite number; the number in `value`.
inline bool read_finite_number(const std::string& input, double& value) {
  return CLI::detail::lexical_cast(input, value) && std::isfinite(value);
}

/// A number in [low, high] (help: "FLOAT in [low - high]", as CLI::Range).
inline CLI::Validator make_range_check(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& input) {
        double value = 0.0;
        if (!read_finite_number(input, value) || value < low || value > high) {
          return "Value " + input + " not in range " + format_number(low) + " to " + format_number(high);
        }
        return std::string();
      },
      "FLOAT in [" + format_number(low) + " - " + format_number(high) + "]");
}

/// An integer in [low, high] (help: "INT in [low - high]", as CLI::Range of ints).
inline CLI::Validator make_range_check(int low, int high) {
  return CLI::Validator(
      [low, high](std::string& input) {
        long long value = 0;
        if (!CLI::detail::lexical_cast(input, value) || value < low || value > high) {
          return "Value " + input + " not in range " + std::to_string(low) + " to " + std::to_string(high);
        }
        return std::string();
      },
      "INT in [" + std::to_string(low) + " - " + std::to_string(high) + "]");
}

/// A finite number > 0 (help: "POSITIVE", as make_positive_check()).
inline CLI::Validator make_positive_check() {
  return CLI::Validator(
      [](std::string& input) {
        double value = 0.0;
        if (!read_finite_number(input, value) || value <= 0.0) return "Value " + input + " is not a positive number";
        return std::string();
      },
      "POSITIVE");
}

/// A finite number ≥ 0 (help: "NONNEGATIVE", as make_non_negative_check()).
inline CLI::Validator make_non_negative_check() {
  return CLI::Validator(
      [](std::string& input) {
        double value = 0.0;
        if (!read_finite_number(input, value) || value < 0.0) return "Value " + input + " is not a number ≥ 0";
        return std::string();
      },
      "NONNEGATIVE");
}

}  // namespace armfarm::cli
