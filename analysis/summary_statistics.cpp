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
  summary.ci_low = summary.ci_high = summary.mean;
  if (summary.has_ci()) {
    const double half_width = calc_student_t_quantile(0.5 + 0.5 * kConfidenceLevel, summary.count - 1) * summary.std_dev / std::sqrt(n);
    summary.ci_low = summary.mean - half_width;
    summary.ci_high = summary.mean + half_width;
  }
  return summary;
}

namespace {

// Continued fraction of the regularized incomplete beta function I_x(a, b), evaluated by the
// modified Lentz method; converges fast for x < (a + 1) / (a + b + 2).
double calc_beta_continued_fraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEpsilon = 1e-15;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double fraction = d;
  for (int m = 1; m <= 500; ++m) {
    const double dm = static_cast<double>(m);
    // Even step: d_{2m} = m (b − m) x / ((a + 2m − 1)(a + 2m)).
    double numerator = dm * (b - dm) * x / ((a + 2.0 * dm - 1.0) * (a + 2.0 * dm));
    d = 1.0 + numerator * d;
    c = 1.0 + numerator / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    fraction *= d * c;
    // Odd step: d_{2m+1} = −(a + m)(a + b + m) x / ((a + 2m)(a + 2m + 1)).
    numerator = -(a + dm) * (a + b + dm) * x / ((a + 2.0 * dm) * (a + 2.0 * dm + 1.0));
    d = 1.0 + numerator * d;
    c = 1.0 + numerator / c;
    if (std::fabs(d) < kTiny) d = kTiny;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    fraction *= step;
    if (std::fabs(step - 1.0) < kEpsilon) break;
  }
  return fraction;
}

double calc_regularized_incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double front = std::exp(log_front);
  if (x < (a + 1.0) / (a + b + 2.0)) return front * calc_beta_continued_fraction(a, b, x) / a;
  return 1.0 - front * calc_beta_continued_fraction(b, a, 1.0 - x) / b;
}

}  // namespace

double calc_student_t_cdf(double t, int degrees_of_freedom) {
  if (degrees_of_freedom < 1) throw std::invalid_argument("Student t needs at least 1 degree of freedom");
  const double nu = static_cast<double>(degrees_of_freedom);
  // P(|T| > |t|) = I_{ν/(ν+t²)}(ν/2, 1/2).
  const double tail = 0.5 * calc_regularized_incomplete_beta(0.5 * nu, 0.5, nu / (nu + t * t));
  return t >= 0.0 ? 1.0 - tail : tail;
}

double calc_student_t_quantile(double p, int degrees_of_freedom) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("a quantile needs 0 < p < 1");
  if (p < 0.5) return -calc_student_t_quantile(1.0 - p, degrees_of_freedom);
  // The CDF is increasing: bracket, then bisect.
  double low = 0.0, high = 1.0;
  while (calc_student_t_cdf(high, degrees_of_freedom) < p) high *= 2.0;
  for (int i = 0; i < 200 && high - low > 1e-13 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (calc_student_t_cdf(middle, degrees_of_freedom) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

double calc_sign_test_p(int successes, int trials) {
  if (trials <= 0) return 1.0;
  // Σ_{i ≥ k} C(n, i) / 2ⁿ, summed in logs to stay finite for large n.
  double p = 0.0;
  for (int i = std::max(successes, 0); i <= trials; ++i) {
    p += std::exp(std::lgamma(trials + 1.0) - std::lgamma(i + 1.0) - std::lgamma(trials - i + 1.0) - trials * std::log(2.0));
  }
  return std::min(p, 1.0);
}

std::string format_mean_ci(const SummaryStatistics& summary, int significant_digits) {
  std::string text = format_table_number(summary.mean, significant_digits);
  if (summary.has_ci()) {
    text += " [" + format_table_number(summary.ci_low, significant_digits) + ", " + format_table_number(summary.ci_high, significant_digits) + "]";
  }
  return text;
}

}  // namespace armfarm
