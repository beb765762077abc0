// The fixed order of decisions: a simulated runner with 1, 2 or 8 threads whose jobs finish in a
// random order takes the same steps (trials, points, rungs, visibility) as the reference
// sequence, and so does one killed mid-search (uncommitted jobs lost) and resumed from what was
// committed.
#include "runner/search/search_sequence.hpp"

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "tests/runner/search/search_test_objectives.hpp"

namespace armfarm::search {
namespace {

double noisy_branin(std::size_t, const SearchPoint& p, std::size_t rung) {
  return testing::calc_branin(p[0], p[1]) + 5.0 * (2.0 - static_cast<double>(rung)) * testing::calc_point_noise(p);
}

// A runner with `threads` workers whose jobs finish in an order drawn from `order_seed`. Stops
// after `kill_after` decisions (uncommitted jobs are lost) when kill_after > 0, else runs to the end.
// `history` may hold a resumed state: its steps and the losses of its committed prefix.
void simulate_runner(const SearchSettings& settings, std::size_t threads, std::uint64_t order_seed, std::size_t kill_after,
                     SearchHistory& history) {
  RandomStream order(order_seed, "completion order");
  std::map<std::size_t, double> finished;  // committed out of order, beyond the prefix
  std::vector<std::size_t> running;
  for (std::size_t s = history.losses.size(); s < history.steps.size(); ++s) running.push_back(s);  // resumed jobs rerun
  const auto finish_one = [&] {
    const std::size_t i = order.uniform_index(running.size());
    const std::size_t s = running[i];
    running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
    const SearchStep& step = history.steps[s];
    finished[s] = noisy_branin(step.trial, history.trials[step.trial].point, step.rung);
    while (finished.count(history.losses.size()) != 0) {
      history.losses.push_back(finished[history.losses.size()]);
      finished.erase(history.losses.size() - 1);
    }
  };
  std::size_t decisions = 0;
  for (;;) {
    if (running.size() >= threads) {
      finish_one();
      continue;
    }
    const NextStep next = calc_next_step(settings, history);
    if (next.needs_loss) {
      finish_one();
      continue;
    }
    if (next.decision.kind != SearchDecision::Kind::run) break;
    add_step(next.decision, next.visible, history);
    running.push_back(history.steps.size() - 1);
    if (kill_after != 0 && ++decisions == kill_after) return;  // kill -9: `running` and `finished` are lost
  }
  while (!running.empty()) finish_one();
}

void expect_same_steps(const SearchHistory& a, const SearchHistory& b, const std::string& what) {
  ASSERT_EQ(a.steps.size(), b.steps.size()) << what;
  ASSERT_EQ(a.trials.size(), b.trials.size()) << what;
  for (std::size_t s = 0; s < a.steps.size(); ++s) {
    EXPECT_EQ(a.steps[s].trial, b.steps[s].trial) << what << " step " << s;
    EXPECT_EQ(a.steps[s].rung, b.steps[s].rung) << what << " step " << s;
    EXPECT_EQ(a.steps[s].visible, b.steps[s].visible) << what << " step " << s;
  }
  for (std::size_t t = 0; t < a.trials.size(); ++t) EXPECT_EQ(a.trials[t].point, b.trials[t].point) << what << " trial " << t;
  EXPECT_EQ(a.losses, b.losses) << what;
}

class SearchSequence : public ::testing::TestWithParam<SearchMethod> {};

TEST_P(SearchSequence, TheStepsAreTheSameAtAnyThreadCountCompletionOrderAndAfterAKill) {
  SearchSettings settings;
  settings.space = testing::make_branin_space();
  settings.space.axes.push_back({"kind", AxisKind::categorical, 0.0, 0.0, 3});
  settings.method = GetParam();
  settings.sampler = SearchSampler::tpe;
  settings.tpe.startup = 6;
  settings.slots = 4;
  settings.rung_cost = {1.0, 3.0, 9.0};
  settings.budget = 25 * 9.0;
  const SearchHistory reference = calc_search_sequence(settings, noisy_branin);
  ASSERT_GT(reference.steps.size(), 20u);
  for (std::size_t threads : {1, 2, 8}) {
    for (std::uint64_t order_seed : {1, 2, 3}) {
      SearchHistory run;
      simulate_runner(settings, threads, order_seed, 0, run);
      expect_same_steps(reference, run, "-j" + std::to_string(threads) + " order " + std::to_string(order_seed));
      // Killed after 17 decisions, resumed (at another thread count) from the committed prefix.
      SearchHistory killed;
      simulate_runner(settings, threads, order_seed, 17, killed);
      EXPECT_LE(killed.losses.size(), killed.steps.size());
      simulate_runner(settings, 3 - std::min<std::size_t>(threads, 2), order_seed + 10, 0, killed);
      expect_same_steps(reference, killed, "killed at -j" + std::to_string(threads));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, SearchSequence,
                         ::testing::Values(SearchMethod::random, SearchMethod::tpe, SearchMethod::asha,
                                           SearchMethod::successive_halving, SearchMethod::hyperband),
                         [](const ::testing::TestParamInfo<SearchMethod>& info) { return std::string(to_string(info.param)); });

TEST(SearchSequence, VisibilityNeverDecreasesAndLagsBySlots) {
  SearchSettings settings;
  settings.space = testing::make_branin_space();
  settings.method = SearchMethod::asha;
  settings.slots = 3;
  settings.rung_cost = {1.0, 3.0, 9.0};
  settings.budget = 100.0;
  const SearchHistory history = calc_search_sequence(settings, noisy_branin);
  std::size_t previous = 0;
  for (std::size_t s = 0; s < history.steps.size(); ++s) {
    EXPECT_GE(history.steps[s].visible, previous);
    EXPECT_GE(history.steps[s].visible + 3, s + 1) << s;  // at most 3 steps undecided-upon
    EXPECT_LE(history.steps[s].visible, s);
    previous = history.steps[s].visible;
  }
  EXPECT_LE(calc_spent(history), 100.0);
}

}  // namespace
}  // namespace armfarm::search
