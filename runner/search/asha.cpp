#include "runner/search/asha.hpp"

namespace armfarm::search {

SearchDecision calc_asha_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible) {
  SearchDecision decision;
  decision.kind = SearchDecision::Kind::run;
  const std::size_t rung_count = settings.rung_cost.size();
  const auto everyone = [](std::size_t) { return true; };
  for (std::size_t k = rung_count - 1; k-- > 0;) {
    const std::vector<std::size_t> ranking = calc_rung_ranking(history, visible, k, everyone);
    const std::size_t promotable = ranking.size() / settings.eta;
    for (std::size_t i = 0; i < promotable; ++i) {
      if (has_step(history, ranking[i], k + 1)) continue;
      decision.trial = ranking[i];
      decision.rung = k + 1;
      return decision;
    }
  }
  if (settings.max_trials != 0 && history.trials.size() >= settings.max_trials) {
    decision.kind = visible < history.steps.size() ? SearchDecision::Kind::wait : SearchDecision::Kind::finished;
    return decision;
  }
  decision.new_trial = true;
  decision.trial = history.trials.size();
  decision.rung = 0;
  decision.point = calc_new_point(settings, history, visible, settings.sampler == SearchSampler::tpe);
  return decision;
}

}  // namespace armfarm::search
