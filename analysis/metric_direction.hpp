#pragma once
// Which way is "better" for each metric the experiment job records, in one table: what
// `armfarm compare` uses to tell a regression from an improvement.
#include <string>

namespace armfarm {

enum class MetricDirection {
  lower_is_better,   ///< errors: nMSE, |feedback|
  higher_is_better,  ///< ff/fb ratio, simulation speed
  neutral,           ///< any change beyond tolerance counts as a regression
  ignored,           ///< machine-dependent timings: not compared unless a tolerances file names them
};

/// The direction of a metric by name (exact names first, then by pattern, e.g. any "*nmse*").
MetricDirection find_metric_direction(const std::string& metric_name);

/// "lower", "higher", "neutral", "ignored".
const char* to_string(MetricDirection direction);
/// Parses the words of to_string; throws std::invalid_argument otherwise.
MetricDirection parse_metric_direction(const std::string& word);

}  // namespace armfarm
