// ASHA's promotions against a hand-worked example (η = 3, 9 trials, rungs 0/1/2), and ASHA on
// multi-fidelity closed forms (Branin, a quadratic on a log-uniform axis, a categorical axis)
// against random search at the same cost.
#include "runner/search/asha.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "runner/search/search_sequence.hpp"
#include "tests/runner/search/search_test_objectives.hpp"

namespace armfarm::search {
namespace {

using testing::calc_best_loss;
using testing::calc_branin;
using testing::calc_median;
using testing::calc_point_noise;

// Each trial's loss at rungs 0 and 1 (rung 2 is never compared: it is the last).
const std::map<std::size_t, std::pair<double, double>> kHandLosses = {
    {0, {5.0, 4.9}}, {1, {3.0, 2.5}}, {2, {8.0, 7.9}}, {3, {1.0, 0.9}}, {4, {6.0, 5.9}},
    {5, {2.0, 1.5}}, {6, {7.0, 6.9}}, {7, {4.0, 3.9}}, {8, {0.5, 0.4}}};

TEST(Asha, PromotionsEqualTheHandWorkedExampleWithEtaThreeAndNineTrials) {
  SearchSettings settings;
  settings.space.axes.push_back({"x", AxisKind::uniform, 0.0, 1.0, 0});
  settings.method = SearchMethod::asha;
  settings.eta = 3;
  settings.max_trials = 9;
  settings.slots = 1;  // each decision sees every earlier loss: the paper's sequential trace
  settings.rung_cost = {1.0, 3.0, 9.0};
  const SearchHistory history = calc_search_sequence(settings, [](std::size_t trial, const SearchPoint&, std::size_t rung) {
    const auto& losses = kHandLosses.at(trial);
    return rung == 0 ? losses.first : rung == 1 ? losses.second : 0.0;
  });
  // By hand (R_k: rung k's seen losses, best first; ⌊|R_k|/3⌋ of them promotable):
  //  1-3  new 0, 1, 2 at rung 0                R_0 = 1,0,2          → 1 promotable: 1
  //  4    promote 1 → rung 1                   R_1 = 1
  //  5    new 3 (R_0's top 1 = 1, promoted)    R_0 = 3,1,0,2        → top 1: 3
  //  6    promote 3 → rung 1                   R_1 = 3,1 (⌊2/3⌋ = 0)
  //  7    new 4                                R_0 = 3,1,0,4,2      (⌊5/3⌋ = 1: 3, promoted)
  //  8    new 5                                R_0 = 3,5,1,0,4,2    → top 2: 3, 5
  //  9    promote 5 → rung 1                   R_1 = 3,5,1          → top 1: 3
  // 10    promote 3 → rung 2
  // 11    new 6                                R_0 of 7             (⌊7/3⌋ = 2: 3, 5 promoted)
  // 12    new 7                                R_0 of 8             (⌊8/3⌋ = 2)
  // 13    new 8                                R_0 = 8,3,5,…        → top 3: 8, 3, 5
  // 14    promote 8 → rung 1                   R_1 = 8,3,5,1        → top 1: 8
  // 15    promote 8 → rung 2
  // then nothing is promotable and the 9 trials are started: finished.
  const std::vector<std::pair<std::size_t, std::size_t>> expected = {
      {0, 0}, {1, 0}, {2, 0}, {1, 1}, {3, 0}, {3, 1}, {4, 0}, {5, 0},
      {5, 1}, {3, 2}, {6, 0}, {7, 0}, {8, 0}, {8, 1}, {8, 2}};
  std::vector<std::pair<std::size_t, std::size_t>> steps;
  for (const SearchStep& step : history.steps) steps.emplace_back(step.trial, step.rung);
  EXPECT_EQ(steps, expected);
  // Costs: 9 new trials at 1, 4 promotions to rung 1 (trials 1, 3, 5, 8) at 3 − 1, 2 to rung 2 at 9 − 3.
  EXPECT_DOUBLE_EQ(calc_spent(history), 9 * 1.0 + 4 * 2.0 + 2 * 6.0);
}

TEST(Asha, ARerunPromotionCostsTheWholeRung) {
  SearchSettings settings;
  settings.rung_cost = {1.0, 3.0, 9.0};
  EXPECT_DOUBLE_EQ(calc_step_cost(settings, true, 2), 6.0);
  settings.resumable = false;
  EXPECT_DOUBLE_EQ(calc_step_cost(settings, true, 2), 9.0);
  EXPECT_DOUBLE_EQ(calc_step_cost(settings, false, 0), 1.0);
}

// Branin whose short runs are noisy: rung r adds up to 8·(2 − r) of a fixed per-point noise, so
// rung 0 ranks roughly and the last rung is exact.
double multi_fidelity_branin(std::size_t, const SearchPoint& p, std::size_t rung) {
  return calc_branin(p[0], p[1]) + 8.0 * (2.0 - static_cast<double>(rung)) * calc_point_noise(p);
}

TEST(Asha, FindsBraninsOptimumRegionAndBeatsRandomAtTheSameCost) {
  // Budget: the cost of 30 full runs (rungs at 1/3/9 units, resumable promotions).
  std::vector<double> asha_best;
  std::vector<double> random_best;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SearchSettings settings;
    settings.space = testing::make_branin_space();
    settings.seed = seed;
    settings.rung_cost = {1.0, 3.0, 9.0};
    settings.budget = 30 * 9.0;
    settings.slots = 2;
    settings.method = SearchMethod::asha;
    asha_best.push_back(calc_best_loss(settings, calc_search_sequence(settings, multi_fidelity_branin)));
    settings.method = SearchMethod::random;
    random_best.push_back(calc_best_loss(settings, calc_search_sequence(settings, multi_fidelity_branin)));
  }
  const double asha = calc_median(asha_best);
  const double random = calc_median(random_best);
  std::printf("ASHA median best %.4f, random %.4f (Branin minimum %.4f)\n", asha, random, testing::kBraninMinimum);
  EXPECT_LT(asha, 1.0);
  EXPECT_LT(asha, random);
}

// The two closed forms of the TPE tests (tpe_sampler_test.cpp) made multi-fidelity: rung r adds
// (2 − r) · `noise` times a fixed per-point value in [0, 1), so short runs rank roughly.
SearchSettings make_asha_settings(std::uint64_t seed, double full_runs) {
  SearchSettings settings;
  settings.seed = seed;
  settings.method = SearchMethod::asha;
  settings.rung_cost = {1.0, 3.0, 9.0};
  settings.budget = full_runs * 9.0;
  settings.slots = 2;
  return settings;
}

TEST(Asha, FindsTheMinimumOfAQuadraticOnALogUniformAxisAtTheCostOfTenFullRuns) {
  // (log10 x − log10 0.003)² on x ∈ [1e-5, 10]; rung noise up to 0.5 (decades²) at rung 0.
  const double target = std::log10(0.003);
  const LossFunction loss = [&](std::size_t, const SearchPoint& p, std::size_t rung) {
    const double d = std::log10(p[0]) - target;
    return d * d + 0.25 * (2.0 - static_cast<double>(rung)) * calc_point_noise(p);
  };
  std::vector<double> asha_best;
  std::vector<double> random_best;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SearchSettings settings = make_asha_settings(seed, 10.0);
    settings.space.axes.push_back({"rate", AxisKind::log_uniform, 1e-5, 10.0, 0});
    asha_best.push_back(calc_best_loss(settings, calc_search_sequence(settings, loss)));
    settings.method = SearchMethod::random;
    random_best.push_back(calc_best_loss(settings, calc_search_sequence(settings, loss)));
  }
  const double asha = calc_median(asha_best);
  const double random = calc_median(random_best);
  std::printf("log-uniform quadratic, cost of 10 full runs: ASHA median best %.2e, random %.2e\n", asha, random);
  EXPECT_LT(std::sqrt(asha), 0.1);  // within a tenth of a decade of 0.003
  EXPECT_LT(asha, random);
}

TEST(Asha, FindsTheBestChoiceOfACategoricalAxisAtTheCostOfTenFullRuns) {
  // Six choices with offsets, choice 4 best by 1.0, plus y² on [−1, 1]; rung noise up to 3 at
  // rung 0 (more than the gap between choices), so rung 0 alone cannot tell them apart.
  const std::vector<double> offset = {3.0, 2.0, 4.0, 5.0, 0.0, 1.0};
  const LossFunction loss = [&](std::size_t, const SearchPoint& p, std::size_t rung) {
    return offset[static_cast<std::size_t>(p[0])] + p[1] * p[1] + 1.5 * (2.0 - static_cast<double>(rung)) * calc_point_noise(p);
  };
  std::vector<double> asha_best;
  std::vector<double> random_best;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    SearchSettings settings = make_asha_settings(seed, 10.0);
    settings.space.axes.push_back({"kind", AxisKind::categorical, 0.0, 0.0, offset.size()});
    settings.space.axes.push_back({"y", AxisKind::uniform, -1.0, 1.0, 0});
    const double best = calc_best_loss(settings, calc_search_sequence(settings, loss));
    EXPECT_LT(best, 0.25) << "seed " << seed;  // choice 4 with |y| < 0.5
    asha_best.push_back(best);
    settings.method = SearchMethod::random;
    random_best.push_back(calc_best_loss(settings, calc_search_sequence(settings, loss)));
  }
  const double asha = calc_median(asha_best);
  const double random = calc_median(random_best);
  std::printf("categorical, cost of 10 full runs: ASHA median best %.4f, random %.4f\n", asha, random);
  EXPECT_LT(asha, random);
}

}  // namespace
}  // namespace armfarm::search
