#pragma once
// Driving a schedule (search_schedule.hpp): the visibility rule applied, one step at a time.
//
// calc_next_step is what every runner calls, whatever its thread count: it starts from the
// visibility floor and, while the method answers "wait", sees one more step — which needs that
// step's loss, so a runner that lacks it waits for its job and asks again. The answer depends
// only on the history, so a runner resuming from the database takes the same decisions.
//
// calc_search_sequence runs a whole search on a loss function (closed-form objectives in the
// tests): each step's loss is computed when a decision first needs it, which is the most
// parallel execution the rule allows and gives the same steps as any other.
#include <cstddef>
#include <functional>

#include "runner/search/search_schedule.hpp"

namespace armfarm::search {

struct NextStep {
  SearchDecision decision;   ///< run or finished (never wait)
  std::size_t visible = 0;   ///< the visibility it was decided with
  bool needs_loss = false;   ///< true: commit the loss of step history.losses.size() and ask again
};

NextStep calc_next_step(const SearchSettings& settings, const SearchHistory& history);

/// The loss of trial `trial` (its point) run to `rung` (lower better; +∞ for a failure).
using LossFunction = std::function<double(std::size_t trial, const SearchPoint& point, std::size_t rung)>;

/// The whole search, every step's loss filled in.
SearchHistory calc_search_sequence(const SearchSettings& settings, const LossFunction& loss);

/// The best loss seen at the last rung after each step (+∞ before the first), for
/// objective-against-cost curves.
std::vector<double> calc_best_so_far(const SearchSettings& settings, const SearchHistory& history);

}  // namespace armfarm::search
