#include "runner/search/search_sequence.hpp"

#include <algorithm>
#include <limits>

namespace armfarm::search {

NextStep calc_next_step(const SearchSettings& settings, const SearchHistory& history) {
  NextStep next;
  next.visible = calc_visible_floor(settings, history);
  for (;;) {
    if (history.losses.size() < next.visible) {
      next.needs_loss = true;
      return next;
    }
    next.decision = calc_next_decision(settings, history, next.visible);
    if (next.decision.kind != SearchDecision::Kind::wait) return next;
    if (next.visible >= history.steps.size()) {
      next.decision = SearchDecision{};  // waiting with everything seen: nothing is left to do
      return next;
    }
    ++next.visible;
  }
}

SearchHistory calc_search_sequence(const SearchSettings& settings, const LossFunction& loss) {
  SearchHistory history;
  const auto commit_next = [&] {
    const SearchStep& step = history.steps[history.losses.size()];
    history.losses.push_back(loss(step.trial, history.trials[step.trial].point, step.rung));
  };
  for (;;) {
    const NextStep next = calc_next_step(settings, history);
    if (next.needs_loss) {
      commit_next();
      continue;
    }
    if (next.decision.kind != SearchDecision::Kind::run) break;
    add_step(next.decision, next.visible, history);
  }
  while (history.losses.size() < history.steps.size()) commit_next();
  return history;
}

std::vector<double> calc_best_so_far(const SearchSettings& settings, const SearchHistory& history) {
  const std::size_t last = settings.rung_cost.size() - 1;
  std::vector<double> best(history.steps.size(), std::numeric_limits<double>::infinity());
  double so_far = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < history.steps.size(); ++s) {
    if (history.steps[s].rung == last && s < history.losses.size()) so_far = std::min(so_far, history.losses[s]);
    best[s] = so_far;
  }
  return best;
}

}  // namespace armfarm::search
