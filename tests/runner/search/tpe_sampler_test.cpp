// TPE on closed-form objectives with known optima: Branin, a 1-D quadratic on a log-uniform axis
// and a categorical axis; each against random search with the same number of trials over 10
// seeds, and the constant liar's effect on parallel proposals.
#include "runner/search/tpe_sampler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "runner/search/search_sequence.hpp"
#include "tests/runner/search/search_test_objectives.hpp"

namespace armfarm::search {
namespace {

using testing::calc_best_loss;
using testing::calc_median;

// The medians over search seeds 1 … `seeds` of the best loss, for TPE and for random search.
struct Medians {
  double tpe = 0.0;
  double random = 0.0;
};
Medians run_both(SearchSettings settings, const LossFunction& loss, std::uint64_t seeds = 10) {
  std::vector<double> tpe;
  std::vector<double> random;
  for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
    settings.seed = seed;
    settings.method = SearchMethod::tpe;
    tpe.push_back(calc_best_loss(settings, calc_search_sequence(settings, loss)));
    settings.method = SearchMethod::random;
    random.push_back(calc_best_loss(settings, calc_search_sequence(settings, loss)));
  }
  return {calc_median(tpe), calc_median(random)};
}

TEST(Tpe, FindsBraninsOptimumRegionInSixtyTrials) {
  SearchSettings settings;
  settings.space = testing::make_branin_space();
  settings.max_trials = 60;
  settings.slots = 4;  // four proposals in flight: the constant liar is used throughout
  // Seeds 1 … 50: with three liars at a time the median of 10 seeds moves by ±0.05 with the
  // liars' bandwidth fraction λ (0.50 to 0.61 for λ 0.62 … 0.72), that of 50 by ±0.01 (0.498 at
  // λ 0.7; 0.475 with the liars at g's bandwidth, the rule before).
  const Medians m = run_both(settings, [](std::size_t, const SearchPoint& p, std::size_t) {
    return testing::calc_branin(p[0], p[1]);
  }, 50);
  std::printf("Branin, 60 trials, seeds 1-50: TPE median best %.4f, random %.4f (minimum %.4f)\n", m.tpe, m.random,
              testing::kBraninMinimum);
  EXPECT_LT(m.tpe, 0.6);
  EXPECT_LT(m.tpe, m.random);
}

TEST(Tpe, FindsTheMinimumOfAQuadraticOnALogUniformAxisInThirtyTrials) {
  // (log10 x − log10 0.003)² on x ∈ [1e-5, 10]: six decades, the optimum near the lower third.
  SearchSettings settings;
  settings.space.axes.push_back({"rate", AxisKind::log_uniform, 1e-5, 10.0, 0});
  settings.max_trials = 30;
  settings.slots = 2;
  const double target = std::log10(0.003);
  const Medians m = run_both(settings, [&](std::size_t, const SearchPoint& p, std::size_t) {
    const double d = std::log10(p[0]) - target;
    return d * d;
  });
  std::printf("log-uniform quadratic, 30 trials: TPE median best %.2e, random %.2e\n", m.tpe, m.random);
  EXPECT_LT(std::sqrt(m.tpe), 0.05);  // within 5 % of a decade of 0.003
  EXPECT_LT(m.tpe, m.random);
}

TEST(Tpe, TheStartupIsAQuarterOfWhatTheBudgetBuysBetweenTwoAndTen) {
  EXPECT_EQ(calc_tpe_startup(3.0), 2u);    // ⌈0.75⌉ = 1, raised to 2
  EXPECT_EQ(calc_tpe_startup(8.0), 2u);
  EXPECT_EQ(calc_tpe_startup(8.5), 3u);    // ⌈2.125⌉
  EXPECT_EQ(calc_tpe_startup(12.0), 3u);
  EXPECT_EQ(calc_tpe_startup(30.0), 8u);   // ⌈7.5⌉
  EXPECT_EQ(calc_tpe_startup(37.0), 10u);  // ⌈9.25⌉
  EXPECT_EQ(calc_tpe_startup(1000.0), 10u);
  EXPECT_EQ(calc_tpe_startup(std::numeric_limits<double>::infinity()), 10u);
}

// What the start-up counts: whole jobs under the schedule's budget check. The bench's fig6_1
// budget (25 % of 48 jobs of 0.2205 CPU-s, as summed and stored) over one job's cost is
// 12.000000000000002, whose ⌈/4⌉ would be 4; a sum that rounds the other way gives 11.99…, 3.
TEST(Tpe, TheStartupCountsTheWholeJobsTheBudgetBuysHoweverItsDivisionRounds) {
  const double cost = 0.22049999999999997, budget = 2.6459999999999999;
  ASSERT_GT(budget / cost, 12.0);
  EXPECT_EQ(calc_whole_jobs(budget, cost), 12.0);
  EXPECT_EQ(calc_whole_jobs(std::nextafter(12.0 * cost, 0.0), cost), 12.0);  // within the check's 1e-12
  EXPECT_EQ(calc_whole_jobs(11.5 * cost, cost), 11.0);
  EXPECT_EQ(calc_whole_jobs(0.5 * cost, cost), 0.0);
  EXPECT_EQ(calc_tpe_startup(calc_whole_jobs(budget, cost)), 3u);
  // It agrees with the schedule: 12 steps of `cost` fit, 13 do not.
  EXPECT_TRUE(fits_budget(12.0 * cost, budget));
  EXPECT_FALSE(fits_budget(13.0 * cost, budget));
}

TEST(Tpe, WithTheBudgetRuleTwelveTrialsBeatRandom) {
  // The log-uniform quadratic of the test above at 12 trials: with the rule's 3 prior draws TPE
  // has nine proposals of its own. (The fixed 10 is printed beside it: on this one-axis
  // problem its two proposals after 10 draws did better, 1.10e-03 against 3.39e-03, so the
  // rule is not asserted to beat it.)
  SearchSettings settings;
  settings.space.axes.push_back({"rate", AxisKind::log_uniform, 1e-5, 10.0, 0});
  settings.max_trials = 12;
  settings.slots = 2;
  const double target = std::log10(0.003);
  const LossFunction loss = [&](std::size_t, const SearchPoint& p, std::size_t) {
    const double d = std::log10(p[0]) - target;
    return d * d;
  };
  settings.tpe.startup = 10;
  const Medians fixed = run_both(settings, loss);
  settings.tpe.startup = calc_tpe_startup(12.0);
  const Medians rule = run_both(settings, loss);
  std::printf("log-uniform quadratic, 12 trials: TPE median best %.2e (start-up %zu), %.2e (start-up 10), random %.2e\n",
              rule.tpe, settings.tpe.startup, fixed.tpe, rule.random);
  EXPECT_LT(rule.tpe, rule.random);
}

// The medians over seeds 1 … 10 of the joint rule, the per-axis rule and random search.
struct RuleMedians {
  double joint = 0.0;
  double independent = 0.0;
  double random = 0.0;
};
RuleMedians run_rules(SearchSettings settings, const LossFunction& loss) {
  settings.tpe.joint = true;
  const Medians joint = run_both(settings, loss);
  settings.tpe.joint = false;
  const Medians independent = run_both(settings, loss);
  return {joint.tpe, independent.tpe, joint.random};
}

TEST(Tpe, TheJointRuleBeatsThePerAxisRuleOnBraninInTwentyTrials) {
  // A small budget: 20 trials, the budget rule's 5 prior draws. The per-axis rule's ℓ for 1 or 2
  // good points is nearly the prior (bandwidth at least half an axis), so it did no better than
  // random (1.52 against 1.28 when written); the joint rule's lone good point spreads over a
  // fifth of each axis (0.67).
  SearchSettings settings;
  settings.space = testing::make_branin_space();
  settings.max_trials = 20;
  settings.slots = 2;
  settings.tpe.startup = calc_tpe_startup(20.0);
  const RuleMedians m = run_rules(settings, [](std::size_t, const SearchPoint& p, std::size_t) {
    return testing::calc_branin(p[0], p[1]);
  });
  std::printf("Branin, 20 trials: joint TPE median best %.4f, per-axis %.4f, random %.4f\n", m.joint, m.independent, m.random);
  EXPECT_LT(m.joint, 1.0);
  EXPECT_LT(m.joint, m.independent);
  EXPECT_LT(m.joint, m.random);
}

TEST(Tpe, TheJointRuleFollowsAnOptimumThatDependsOnACategoricalChoice) {
  // x's best value depends on the choice: (log10 x − log10 0.003)² with choice 0, (log10 x)² +
  // 0.05 with choice 1. The per-axis rule multiplies the good x of one choice with the other
  // choice; the joint rule keeps each good point's pair. 12 trials (3 prior draws).
  SearchSettings settings;
  settings.space.axes.push_back({"x", AxisKind::log_uniform, 1e-5, 10.0, 0});
  settings.space.axes.push_back({"c", AxisKind::categorical, 0.0, 0.0, 2});
  settings.max_trials = 12;
  settings.slots = 2;
  settings.tpe.startup = calc_tpe_startup(12.0);
  const RuleMedians m = run_rules(settings, [](std::size_t, const SearchPoint& p, std::size_t) {
    const double d = std::log10(p[0]) - (p[1] == 0.0 ? std::log10(0.003) : 0.0);
    return d * d + (p[1] == 0.0 ? 0.0 : 0.05);
  });
  std::printf("choice-dependent optimum, 12 trials: joint TPE median best %.2e, per-axis %.2e, random %.2e\n", m.joint,
              m.independent, m.random);
  EXPECT_LT(m.joint, 0.02);  // on choice 0 within 0.14 decades of 0.003
  EXPECT_LT(m.joint, m.independent);
  EXPECT_LT(m.joint, m.random);
}

TEST(Tpe, SettlesOnTheBestChoiceOfACategoricalAxis) {
  // Six choices with offsets; choice 4 is best by 1.0 over the next, plus a quadratic in y.
  const std::vector<double> offset = {3.0, 2.0, 4.0, 5.0, 0.0, 1.0};
  SearchSettings settings;
  settings.space.axes.push_back({"kind", AxisKind::categorical, 0.0, 0.0, offset.size()});
  settings.space.axes.push_back({"y", AxisKind::uniform, -1.0, 1.0, 0});
  settings.max_trials = 40;
  settings.slots = 2;
  const LossFunction loss = [&](std::size_t, const SearchPoint& p, std::size_t) {
    return offset[static_cast<std::size_t>(p[0])] + p[1] * p[1];
  };
  int best_choice_late = 0;
  int late = 0;
  int found = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    settings.seed = seed;
    settings.method = SearchMethod::tpe;
    const SearchHistory history = calc_search_sequence(settings, loss);
    // After the 10 start-up draws, how often TPE proposes the best choice (random: 1 in 6).
    for (std::size_t t = 20; t < history.trials.size(); ++t, ++late) best_choice_late += history.trials[t].point[0] == 4.0;
    found += calc_best_loss(settings, history) < 0.1;  // choice 4 with |y| < 0.32
  }
  std::printf("categorical: TPE finds the best choice in %d of 10 seeds and proposes it in %d of its last %d trials\n", found,
              best_choice_late, late);
  // 9 of 10: under the joint rule seed 7 settles on choice 5 (loss 1.0003), the next best. A
  // choice no good point has is proposed only from the prior's share of ℓ (1/(m+1)) and the
  // kernels' ε/K, so a choice the start-up misses can stay unseen (the per-axis rule found it in
  // 10 of 10 seeds here).
  EXPECT_GE(found, 9);
  EXPECT_GT(best_choice_late, late / 2);
}

// Of 400 proposals (trials 0 … 399 of seed 1) on x ∈ [0, 1] after 12 evenly spread observations
// of (x − 0.3)², how many lie within 0.05 of 0.3, without pending points and with three pending
// at 0.3 (the liars).
struct NearPending {
  int alone = 0;
  int liars = 0;
};
NearPending count_near_pending(const TpeSettings& settings) {
  SearchSpace space;
  space.axes.push_back({"x", AxisKind::uniform, 0.0, 1.0, 0});
  std::vector<Observation> known;
  for (std::size_t i = 0; i < 12; ++i) {
    const double x = (static_cast<double>(i) + 0.5) / 12.0;
    known.push_back({i, {x}, (x - 0.3) * (x - 0.3)});
  }
  std::vector<Observation> pending;
  for (std::size_t i = 0; i < 3; ++i) pending.push_back({12 + i, {0.3}, 0.0});
  NearPending near;
  for (std::size_t trial = 0; trial < 400; ++trial) {
    RandomStream a = make_trial_stream(1, trial);
    RandomStream b = make_trial_stream(1, trial);
    near.alone += std::abs(calc_tpe_point(space, settings, known, {}, a)[0] - 0.3) < 0.05;
    near.liars += std::abs(calc_tpe_point(space, settings, known, pending, b)[0] - 0.3) < 0.05;
  }
  return near;
}

TEST(Tpe, TheConstantLiarMovesTheJointRulesNextProposalAwayFromPendingPoints) {
  // The default (joint) rule: the three liars are components of g with 0.7 times ℓ's bandwidth
  // (ℓ's σ 0.2 · 3^(−1/5) = 0.161, the liars' 0.113), a dip in ℓ/g around 0.3 (parzen_estimator.hpp,
  // "Liars"). With the liars in g at g's own bandwidth (the rule before) 392 of the 400 proposals
  // were within 0.05 of 0.3, against 400 without liars; with this rule 34 (mean distance 0.072).
  TpeSettings settings;
  ASSERT_TRUE(settings.joint);
  settings.startup = 4;
  const NearPending near = count_near_pending(settings);
  std::printf("joint rule: %d of 400 proposals within 0.05 of the pending point with liars, %d without\n", near.liars,
              near.alone);
  EXPECT_LT(near.liars, near.alone / 4) << near.liars << " vs " << near.alone;
}

TEST(Tpe, TheConstantLiarMovesThePerAxisRulesNextProposalAwayFromPendingPoints) {
  // The per-axis rule: three coinciding liars get its narrowest bandwidth (1/13 of the axis), a
  // sharp dip in ℓ/g.
  TpeSettings settings;
  settings.joint = false;
  settings.startup = 4;
  const NearPending near = count_near_pending(settings);
  std::printf("per-axis rule: %d of 400 proposals within 0.05 of the pending point with liars, %d without\n", near.liars,
              near.alone);
  EXPECT_LT(near.liars, 0.7 * near.alone) << near.liars << " vs " << near.alone;
}

}  // namespace
}  // namespace armfarm::search
