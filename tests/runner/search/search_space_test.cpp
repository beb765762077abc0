// Prior draws: inside the bounds, whole numbers on integer axes, the log-uniform median at the
// geometric mean of the bounds, and one stream per trial.
#include "runner/search/search_space.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace armfarm::search {
namespace {

SearchSpace make_mixed_space() {
  SearchSpace space;
  space.axes.push_back({"a", AxisKind::uniform, -2.0, 3.0, 0});
  space.axes.push_back({"b", AxisKind::log_uniform, 1e-4, 1e2, 0});
  space.axes.push_back({"c", AxisKind::integer, 2.0, 6.0, 0});
  space.axes.push_back({"d", AxisKind::categorical, 0.0, 0.0, 4});
  return space;
}

TEST(SearchSpace, PriorDrawsStayInsideTheirAxesAndFollowTheirScale) {
  const SearchSpace space = make_mixed_space();
  RandomStream stream(7, "test");
  std::vector<double> log_values;
  std::vector<int> integer_counts(7, 0);
  std::vector<int> choice_counts(4, 0);
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const SearchPoint p = calc_random_point(space, stream);
    ASSERT_EQ(p.size(), 4u);
    EXPECT_GE(p[0], -2.0);
    EXPECT_LE(p[0], 3.0);
    EXPECT_GE(p[1], 1e-4);
    EXPECT_LE(p[1], 1e2);
    ASSERT_EQ(p[2], std::round(p[2]));
    ASSERT_GE(p[2], 2.0);
    ASSERT_LE(p[2], 6.0);
    ++integer_counts[static_cast<int>(p[2])];
    ++choice_counts[static_cast<int>(p[3])];
    log_values.push_back(std::log10(p[1]));
  }
  // Log-uniform on [1e-4, 1e2]: log10 uniform on [−4, 2], median −1, a sixth below −3.
  std::sort(log_values.begin(), log_values.end());
  EXPECT_NEAR(log_values[n / 2], -1.0, 0.1);
  EXPECT_NEAR(static_cast<double>(std::lower_bound(log_values.begin(), log_values.end(), -3.0) - log_values.begin()) / n,
              1.0 / 6.0, 0.015);
  // Every whole number 2 … 6 equally likely (the end cells are as wide as the inner ones).
  for (int k = 2; k <= 6; ++k) EXPECT_NEAR(integer_counts[k] / static_cast<double>(n), 0.2, 0.015) << k;
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(choice_counts[c] / static_cast<double>(n), 0.25, 0.015) << c;
}

TEST(SearchSpace, EachTrialHasItsOwnStream) {
  const SearchSpace space = make_mixed_space();
  RandomStream first = make_trial_stream(11, 3);
  RandomStream again = make_trial_stream(11, 3);
  RandomStream other = make_trial_stream(11, 4);
  const SearchPoint a = calc_random_point(space, first);
  EXPECT_EQ(a, calc_random_point(space, again));
  EXPECT_NE(a, calc_random_point(space, other));
}

TEST(SearchSpace, InternalCoordinatesRoundTrip) {
  const SearchAxis log_axis{"b", AxisKind::log_uniform, 1e-3, 10.0, 0};
  EXPECT_NEAR(calc_axis_value(log_axis, calc_internal_coordinate(log_axis, 0.25)), 0.25, 1e-15);
  const InternalInterval interval = calc_internal_interval(log_axis);
  EXPECT_NEAR(interval.low, std::log(1e-3), 1e-15);
  const SearchAxis integer_axis{"c", AxisKind::integer, 1.0, 5.0, 0};
  EXPECT_EQ(calc_axis_value(integer_axis, 3.4), 3.0);
  EXPECT_EQ(calc_axis_value(integer_axis, 5.49), 5.0);
  EXPECT_EQ(calc_axis_value(integer_axis, 0.51), 1.0);
}

}  // namespace
}  // namespace armfarm::search
