#include "analysis/summary_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace armfarm {

Aggregate parse_aggregate(const std::string& word) {
  if (word == "mean") return Aggregate::mean;
  if (word == "median") return Aggregate::median;
  if (word == "min") return Aggregate::min;
  if (word == "max") return Aggregate::max;
  throw std::invalid_argument("--agg must be mean, median, min or max, not '" + word + "'");
}

const char* to_string(Aggregate aggregate) {
  switch (aggregate) {
    case Aggregate::mean: return "mean";
    case Aggregate::median: return "median";
    case Aggregate::min: return "min";
    case Aggregate::max: return "max";
  }
  return "mean";
}

double SummaryStatistics::value(Aggregate aggregate) const {
  switch (aggregate) {
    case Aggregate::mean: return mean;
    case Aggregate::median: return median;
    case Aggregate::min: return min;
    case Aggregate::max: return max;
  }
  return mean;
}

SummaryStatistics calc_summary_statistics(std::vector<double> values) {
  SummaryStatistics summary;
  summary.count = static_cast<int>(values.size());
  if (values.empty()) return summary;
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  summary.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  summary.min = values.front();
  summary.max = values.back();
  const std::size_t middle = values.size() / 2;
  summary.median = values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
  if (values.size() > 1) {
    double sum_squares = 0.0;
    for (double v : values) sum_squares += (v - summary.mean) * (v - summary.mean);
    summary.std_dev = std::sqrt(sum_squares / (n - 1.0));
  }
  return summary;
}

std::string format_number(double value, int significant_digits) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const double magnitude = std::fabs(value);
  if (value != 0.0 && (magnitude < 1e-2 || magnitude >= 1e5)) {
    std::snprintf(buffer, sizeof buffer, "%.*e", significant_digits - 1, value);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.*g", significant_digits, value);
  }
  return buffer;
}

}  // namespace armfarm
