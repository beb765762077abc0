// The summary statistics of a table cell: the confidence interval, the Student-t quantile and
// the sign test against hand computations, closed forms and printed tables.
#include "analysis/summary_statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace armfarm {
namespace {

// The interval against a hand computation: 1, 2, 3, 4, 5 have mean 3, std √2.5 = 1.581139,
// standard error 0.707107; t(0.975, 4) = 2.776445 (printed t tables), so 3 ∓ 1.963243.
TEST(SummaryStatistics, ConfidenceIntervalEqualsTheHandComputation) {
  const SummaryStatistics five = calc_summary_statistics({5.0, 1.0, 4.0, 2.0, 3.0});
  EXPECT_EQ(five.count, 5);
  ASSERT_TRUE(five.has_ci());
  EXPECT_NEAR(five.ci_low, 3.0 - 1.963243, 2e-6);
  EXPECT_NEAR(five.ci_high, 3.0 + 1.963243, 2e-6);
  // Two values: t(0.975, 1) = tan(0.475π) = 12.706205 in closed form; 0.5 ∓ 12.706205·0.5.
  const SummaryStatistics two = calc_summary_statistics({0.0, 1.0});
  EXPECT_NEAR(two.ci_high, 0.5 + 0.5 * std::tan(0.475 * M_PI), 1e-9);
  EXPECT_NEAR(two.ci_low, 0.5 - 0.5 * std::tan(0.475 * M_PI), 1e-9);
  // One value has no interval; equal values an empty one.
  const SummaryStatistics one = calc_summary_statistics({0.7});
  EXPECT_FALSE(one.has_ci());
  EXPECT_EQ(format_mean_ci(one), "0.7");
  const SummaryStatistics same = calc_summary_statistics({0.7, 0.7, 0.7});
  EXPECT_DOUBLE_EQ(same.ci_low, 0.7);
  EXPECT_DOUBLE_EQ(same.ci_high, 0.7);
  EXPECT_EQ(format_mean_ci(five), "3 [1.037, 4.963]");
}

// The quantile against closed forms (ν = 1: tan(π(p − ½)); ν = 2: (2p − 1)/√(2p(1 − p))) and
// against printed tables for larger ν (t(0.975, 9) = 2.262157, t(0.975, 29) = 2.045230); it
// tends to the normal 1.959964.
TEST(SummaryStatistics, StudentTQuantileMatchesClosedFormsAndTables) {
  for (double p : {0.6, 0.9, 0.975, 0.995}) {
    EXPECT_NEAR(calc_student_t_quantile(p, 1), std::tan(M_PI * (p - 0.5)), 1e-9 * std::tan(M_PI * (p - 0.5))) << p;
    EXPECT_NEAR(calc_student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-10) << p;
  }
  EXPECT_NEAR(calc_student_t_quantile(0.975, 9), 2.262157, 1e-6);
  EXPECT_NEAR(calc_student_t_quantile(0.975, 29), 2.045230, 1e-6);
  EXPECT_NEAR(calc_student_t_quantile(0.975, 100000), 1.959964, 1e-4);
  EXPECT_NEAR(calc_student_t_quantile(0.025, 4), -2.776445, 1e-6);
  EXPECT_NEAR(calc_student_t_cdf(0.0, 7), 0.5, 1e-15);
}

// The one-sided sign test: 5 of 5 gives 1/32, 4 of 5 gives 6/32, 9 of 10 gives 11/1024.
TEST(SummaryStatistics, SignTestIsTheBinomialTail) {
  EXPECT_NEAR(calc_sign_test_p(5, 5), 1.0 / 32, 1e-15);
  EXPECT_NEAR(calc_sign_test_p(4, 5), 6.0 / 32, 1e-14);
  EXPECT_NEAR(calc_sign_test_p(9, 10), 11.0 / 1024, 1e-14);
  EXPECT_NEAR(calc_sign_test_p(0, 4), 1.0, 1e-14);
  EXPECT_EQ(calc_sign_test_p(0, 0), 1.0);
}

}  // namespace
}  // namespace armfarm
