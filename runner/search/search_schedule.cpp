#include "runner/search/search_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "runner/search/asha.hpp"
#include "runner/search/hyperband.hpp"

namespace armfarm::search {
namespace {

// random and tpe: every step a new trial run to the last rung.
SearchDecision calc_full_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible) {
  SearchDecision decision;
  if (settings.max_trials != 0 && history.trials.size() >= settings.max_trials) return decision;  // finished
  decision.kind = SearchDecision::Kind::run;
  decision.new_trial = true;
  decision.trial = history.trials.size();
  decision.rung = settings.rung_cost.size() - 1;
  decision.point = calc_new_point(settings, history, visible, settings.method == SearchMethod::tpe);
  return decision;
}

}  // namespace

const char* to_string(SearchMethod method) {
  switch (method) {
    case SearchMethod::random: return "random";
    case SearchMethod::tpe: return "tpe";
    case SearchMethod::asha: return "asha";
    case SearchMethod::successive_halving: return "successive_halving";
    case SearchMethod::hyperband: return "hyperband";
  }
  return "?";
}

const char* to_string(SearchSampler sampler) { return sampler == SearchSampler::tpe ? "tpe" : "random"; }

std::size_t calc_visible_floor(const SearchSettings& settings, const SearchHistory& history) {
  const std::size_t n = history.steps.size();
  const std::size_t slots = std::max<std::size_t>(settings.slots, 1);
  const std::size_t lag_floor = n + 1 > slots ? n + 1 - slots : 0;
  const std::size_t previous = history.steps.empty() ? 0 : history.steps.back().visible;
  return std::max(previous, lag_floor);
}

double calc_step_cost(const SearchSettings& settings, bool promotion, std::size_t rung) {
  const double full = settings.rung_cost[rung];
  if (promotion && settings.resumable && rung > 0) return full - settings.rung_cost[rung - 1];
  return full;
}

double calc_spent(const SearchHistory& history) {
  double spent = 0.0;
  for (const SearchStep& step : history.steps) spent += step.cost;
  return spent;
}

SearchDecision calc_next_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible) {
  SearchDecision decision;
  switch (settings.method) {
    case SearchMethod::random:
    case SearchMethod::tpe: decision = calc_full_decision(settings, history, visible); break;
    case SearchMethod::asha: decision = calc_asha_decision(settings, history, visible); break;
    case SearchMethod::successive_halving:
    case SearchMethod::hyperband: decision = calc_bracket_decision(settings, history, visible); break;
  }
  if (decision.kind != SearchDecision::Kind::run) return decision;
  decision.cost = calc_step_cost(settings, !decision.new_trial, decision.rung);
  // The budget: a decision that does not fit ends the search. (A smaller step might still fit;
  // taking it would make the end depend on which step happened to be next, so none is taken.)
  if (!fits_budget(calc_spent(history) + decision.cost, settings.budget)) return SearchDecision{};
  return decision;
}

bool fits_budget(double spent, double budget) { return spent <= budget * (1.0 + 1e-12); }

double calc_whole_jobs(double budget, double cost) {
  if (!(cost > 0.0) || !std::isfinite(budget)) return std::numeric_limits<double>::infinity();
  double jobs = std::floor(budget / cost);
  while (fits_budget((jobs + 1.0) * cost, budget)) jobs += 1.0;   // 11.999… that buys 12
  while (jobs > 0.0 && !fits_budget(jobs * cost, budget)) jobs -= 1.0;  // 12.000…1 that buys 11
  return jobs;
}

void add_step(const SearchDecision& decision, std::size_t visible, SearchHistory& history) {
  if (decision.new_trial) history.trials.push_back({decision.point, decision.bracket});
  history.steps.push_back({decision.trial, decision.rung, visible, decision.cost});
}

std::vector<std::size_t> calc_rung_ranking(const SearchHistory& history, std::size_t visible, std::size_t rung,
                                           const std::function<bool(std::size_t)>& include) {
  std::vector<std::pair<double, std::size_t>> members;
  for (std::size_t s = 0; s < visible; ++s) {
    const SearchStep& step = history.steps[s];
    if (step.rung != rung || !include(step.trial)) continue;
    members.emplace_back(history.losses[s], step.trial);
  }
  std::sort(members.begin(), members.end());  // failed jobs carry +inf, never NaN
  std::vector<std::size_t> trials;
  trials.reserve(members.size());
  for (const auto& member : members) trials.push_back(member.second);
  return trials;
}

bool has_step(const SearchHistory& history, std::size_t trial, std::size_t rung) {
  return std::any_of(history.steps.begin(), history.steps.end(),
                     [&](const SearchStep& step) { return step.trial == trial && step.rung == rung; });
}

SearchPoint calc_new_point(const SearchSettings& settings, const SearchHistory& history, std::size_t visible, bool tpe) {
  const std::size_t trial = history.trials.size();
  RandomStream stream = make_trial_stream(settings.seed, trial);
  if (!tpe) return calc_random_point(settings.space, stream);
  // Observations from the highest rung with `startup` seen losses (the longest-trained evidence
  // that is plentiful enough; rung 0 when none is).
  std::size_t rung_count = settings.rung_cost.size();
  std::vector<std::size_t> seen_at(rung_count, 0);
  for (std::size_t s = 0; s < visible; ++s) ++seen_at[history.steps[s].rung];
  std::size_t rung = 0;
  for (std::size_t r = rung_count; r-- > 0;) {
    if (seen_at[r] >= settings.tpe.startup) {
      rung = r;
      break;
    }
  }
  std::vector<Observation> known;
  std::vector<bool> seen(history.trials.size(), false);
  for (std::size_t s = 0; s < visible; ++s) {
    const SearchStep& step = history.steps[s];
    if (step.rung != rung) continue;
    known.push_back({step.trial, history.trials[step.trial].point, history.losses[s]});
    seen[step.trial] = true;
  }
  // Pending: trials with a step not seen yet and no seen loss at the rung used.
  std::vector<Observation> pending;
  std::vector<bool> listed(history.trials.size(), false);
  for (std::size_t s = visible; s < history.steps.size(); ++s) {
    const std::size_t t = history.steps[s].trial;
    if (seen[t] || listed[t]) continue;
    listed[t] = true;
    pending.push_back({t, history.trials[t].point, 0.0});
  }
  return calc_tpe_point(settings.space, settings.tpe, known, pending, stream);
}

}  // namespace armfarm::search
