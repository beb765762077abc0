#pragma once
// Aggregates of a metric over the repeats (seeds) of one table cell, and number formatting for
// reading (significant digits; scientific notation for very small or large values, as the
// thesis prints nMSE).
#include <string>
#include <vector>

namespace armfarm {

enum class Aggregate { mean, median, min, max };

/// Parses "mean", "median", "min", "max"; throws std::invalid_argument otherwise.
Aggregate parse_aggregate(const std::string& word);
const char* to_string(Aggregate aggregate);

/// Summary of n values. `std_dev` is the sample standard deviation (n − 1), 0 for n < 2.
struct SummaryStatistics {
  int count = 0;
  double mean = 0.0;
  double std_dev = 0.0;
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
  double value(Aggregate aggregate) const;
};

/// Precondition: none (an empty list gives count 0).
SummaryStatistics calc_summary_statistics(std::vector<double> values);

/// `significant_digits` significant digits; scientific ("1.950e-03") when |x| < 1e-2 or ≥ 1e5.
std::string format_number(double value, int significant_digits = 4);

}  // namespace armfarm
