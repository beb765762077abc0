#pragma once
// Synchronous successive halving (Jamieson & Talwalkar, AISTATS 2016) and Hyperband's brackets of
// it (Li, Jamieson, DeSalvo, Rostamizadeh & Talwalkar, JMLR 18(185), 2018, algorithm 1), over the
// job's learning checkpoints as rungs 0 … K.
//
// A bracket with start rung r_0 and n trials: start n new trials at r_0; when every one of the
// n_k trials run to rung k has its loss seen, promote the best ⌊n_k / η⌋ to rung k+1; stop at
// rung K or when ⌊n_k / η⌋ = 0.
//
// successive_halving: every bracket starts at rung 0 with n = bracket_size (default η^K).
// hyperband: bracket b has s = K − (b mod (K+1)) halvings: it starts at rung K − s with
//   n = ⌈(K+1)/(s+1) · η^s⌉
// trials (the paper's n for R = η^K, counted in rungs), so one round of K+1 brackets runs from
// the most exploratory (many trials, all rungs) to plain full-budget runs; rounds repeat until
// the budget ends.
//
// Each decision walks the brackets oldest first and takes the first thing one of them can do
// (start its next trial, or its next promotion in rank order). A bracket whose rung still has
// unseen losses waits; when all existing brackets wait or are done, the next bracket starts, so
// threads stay busy while a rung fills.
#include <cstddef>

#include "runner/search/search_schedule.hpp"

namespace armfarm::search {

/// Bracket b's start rung and size.
struct BracketShape {
  std::size_t start_rung = 0;
  std::size_t size = 1;
};
BracketShape calc_bracket_shape(const SearchSettings& settings, std::size_t bracket);

SearchDecision calc_bracket_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible);

}  // namespace armfarm::search
