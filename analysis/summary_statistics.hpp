#pragma once
// Aggregates of a metric over the repeats (seeds) of one table cell: mean, standard deviation,
// the 95 % confidence interval of the mean (Student t with n − 1 degrees of freedom), and the
// mean with its interval as text (cells: format_table_number, base/number_format.hpp).
#include "base/number_format.hpp"

#include <string>
#include <vector>

namespace armfarm {

enum class Aggregate { mean, median, min, max };

/// Parses "mean", "median", "min", "max"; throws std::invalid_argument otherwise.
Aggregate parse_aggregate(const std::string& word);
const char* to_string(Aggregate aggregate);

/// Summary of n values. `std_dev` is the sample standard deviation (n − 1), 0 for n < 2.
/// [ci_low, ci_high] is mean ∓ t(0.975, n − 1)·std_dev/√n, the two-sided 95 % Student-t
/// interval of the mean over the repeats; it equals [mean, mean] for n < 2 (`has_ci` false).
struct SummaryStatistics {
  int count = 0;
  double mean = 0.0;
  double std_dev = 0.0;
  double ci_low = 0.0;
  double ci_high = 0.0;
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
  double value(Aggregate aggregate) const;
  bool has_ci() const { return count >= 2; }
};

/// The confidence level of every interval armfarm prints.
inline constexpr double kConfidenceLevel = 0.95;

/// The p-quantile of Student's t distribution with `degrees_of_freedom` ≥ 1, for 0 < p < 1
/// (from the regularized incomplete beta function, solved by bisection to ~1e-12 relative).
double calc_student_t_quantile(double p, int degrees_of_freedom);

/// P(T ≤ t) for Student's t with `degrees_of_freedom` ≥ 1.
double calc_student_t_cdf(double t, int degrees_of_freedom);

/// One-sided sign test: P(X ≥ successes) for X ~ Binomial(trials, 1/2); 1 for trials = 0.
double calc_sign_test_p(int successes, int trials);

/// Precondition: none (an empty list gives count 0).
SummaryStatistics calc_summary_statistics(std::vector<double> values);

/// "mean [low, high]" with `significant_digits` each; the mean alone when there is no interval.
std::string format_mean_ci(const SummaryStatistics& summary, int significant_digits = 4);

}  // namespace armfarm
