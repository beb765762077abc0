#include "runner/search/hyperband.hpp"

#include <cmath>

namespace armfarm::search {
namespace {

std::size_t power(std::size_t base, std::size_t exponent) {
  std::size_t result = 1;
  for (std::size_t i = 0; i < exponent; ++i) result *= base;
  return result;
}

}  // namespace

BracketShape calc_bracket_shape(const SearchSettings& settings, std::size_t bracket) {
  const std::size_t k = settings.rung_cost.size() - 1;
  if (settings.method == SearchMethod::successive_halving) {
    return {0, settings.bracket_size != 0 ? settings.bracket_size : power(settings.eta, k)};
  }
  const std::size_t s = k - bracket % (k + 1);
  // ⌈(K+1)/(s+1) · η^s⌉ in whole numbers: ⌈a/b⌉ = (a + b − 1) / b.
  const std::size_t numerator = (k + 1) * power(settings.eta, s);
  return {k - s, (numerator + s) / (s + 1)};
}

SearchDecision calc_bracket_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible) {
  const std::size_t last_rung = settings.rung_cost.size() - 1;
  std::size_t brackets = 0;
  for (const SearchTrial& trial : history.trials) brackets = std::max(brackets, trial.bracket + 1);

  SearchDecision decision;
  decision.kind = SearchDecision::Kind::run;
  const auto start_trial = [&](std::size_t bracket) {
    decision.new_trial = true;
    decision.trial = history.trials.size();
    decision.rung = calc_bracket_shape(settings, bracket).start_rung;
    decision.bracket = bracket;
    decision.point = calc_new_point(settings, history, visible, settings.sampler == SearchSampler::tpe);
    return decision;
  };
  for (std::size_t b = 0; b < brackets; ++b) {
    const BracketShape shape = calc_bracket_shape(settings, b);
    const auto in_bracket = [&](std::size_t t) { return history.trials[t].bracket == b; };
    std::size_t started = 0;
    for (const SearchTrial& trial : history.trials) started += trial.bracket == b ? 1 : 0;
    if (started < shape.size) return start_trial(b);
    for (std::size_t k = shape.start_rung; k < last_rung; ++k) {
      std::size_t issued = 0;
      std::size_t promoted = 0;
      for (std::size_t t = 0; t < history.trials.size(); ++t) {
        if (!in_bracket(t)) continue;
        issued += has_step(history, t, k) ? 1 : 0;
        promoted += has_step(history, t, k + 1) ? 1 : 0;
      }
      const std::vector<std::size_t> ranking = calc_rung_ranking(history, visible, k, in_bracket);
      if (ranking.size() < issued) break;  // this rung still has unseen losses: the bracket waits
      const std::size_t quota = issued / settings.eta;
      if (promoted < quota) {
        for (std::size_t trial : ranking) {
          if (has_step(history, trial, k + 1)) continue;
          decision.trial = trial;
          decision.rung = k + 1;
          return decision;
        }
      }
      if (quota == 0) break;  // the bracket is done
    }
  }
  return start_trial(brackets);
}

}  // namespace armfarm::search
