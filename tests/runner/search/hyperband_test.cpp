// Hyperband's bracket sizes (the paper's n = ⌈(s_max+1)/(s+1)·η^s⌉) and a synchronous halving
// that promotes only full rungs, best first.
#include "runner/search/hyperband.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "runner/search/search_sequence.hpp"

namespace armfarm::search {
namespace {

TEST(Hyperband, BracketShapesFollowThePaper) {
  SearchSettings settings;
  settings.method = SearchMethod::hyperband;
  settings.eta = 3;
  settings.rung_cost = {1.0, 3.0, 9.0, 27.0};  // K = 3: s = 3, 2, 1, 0
  // n = ⌈4/4·27⌉ = 27, ⌈4/3·9⌉ = 12, ⌈4/2·3⌉ = 6, ⌈4/1·1⌉ = 4 (Li et al. 2018, table 1 for R = 27).
  const std::vector<std::pair<std::size_t, std::size_t>> expected = {{0, 27}, {1, 12}, {2, 6}, {3, 4}, {0, 27}};
  for (std::size_t b = 0; b < expected.size(); ++b) {
    const BracketShape shape = calc_bracket_shape(settings, b);
    EXPECT_EQ(shape.start_rung, expected[b].first) << b;
    EXPECT_EQ(shape.size, expected[b].second) << b;
  }
}

TEST(SuccessiveHalving, PromotesTheBestThirdOfEachFullRung) {
  SearchSettings settings;
  settings.space.axes.push_back({"x", AxisKind::uniform, 0.0, 1.0, 0});
  settings.method = SearchMethod::successive_halving;
  settings.eta = 3;
  settings.slots = 1;
  settings.rung_cost = {1.0, 3.0, 9.0};
  settings.budget = 9 * 1.0 + 3 * 2.0 + 1 * 6.0;  // exactly one bracket of 9
  // Loss: trial t at rung r is (t * 7 mod 9) − r, so rung 0's order is 0, 4, 8, 3, 7, 2, 6, 1, 5.
  const SearchHistory history = calc_search_sequence(settings, [](std::size_t t, const SearchPoint&, std::size_t r) {
    return static_cast<double>((t * 7) % 9) - static_cast<double>(r);
  });
  std::vector<std::pair<std::size_t, std::size_t>> steps;
  for (const SearchStep& step : history.steps) steps.emplace_back(step.trial, step.rung);
  std::vector<std::pair<std::size_t, std::size_t>> expected;
  for (std::size_t t = 0; t < 9; ++t) expected.emplace_back(t, 0);
  expected.insert(expected.end(), {{0, 1}, {4, 1}, {8, 1}, {0, 2}});
  EXPECT_EQ(steps, expected);
}

TEST(SuccessiveHalving, ARungWithUnseenLossesWaitsAndTheNextBracketStarts) {
  SearchSettings settings;
  settings.space.axes.push_back({"x", AxisKind::uniform, 0.0, 1.0, 0});
  settings.method = SearchMethod::successive_halving;
  settings.bracket_size = 3;
  settings.slots = 3;  // the decision after the third trial sees only the first
  settings.rung_cost = {1.0, 3.0};
  settings.budget = 7.0;  // 3 + 2 new trials, then the promotion of trial 0 (2)
  const SearchHistory history = calc_search_sequence(settings, [](std::size_t t, const SearchPoint&, std::size_t) {
    return static_cast<double>(t);
  });
  ASSERT_GE(history.trials.size(), 4u);
  EXPECT_EQ(history.trials[3].bracket, 1u);  // started while bracket 0's rung 0 was not all seen
  EXPECT_TRUE(std::any_of(history.steps.begin(), history.steps.end(),
                          [](const SearchStep& s) { return s.trial == 0 && s.rung == 1; }));
}

}  // namespace
}  // namespace armfarm::search
