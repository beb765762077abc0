#pragma once
// Asynchronous successive halving (ASHA; Li, Jamieson, Rostamizadeh, Gonina, Ben-tzur, Hardt,
// Recht & Talwalkar, "A System for Massively Parallel Hyperparameter Tuning", MLSys 2020,
// algorithm 2), over the job's learning checkpoints as rungs 0 … K.
//
// Each decision, over the losses seen so far (search_schedule.hpp, "The fixed order"):
//   for k = K−1 down to 0:
//     R_k = the trials with a seen loss at rung k, best first;
//     the promotable set is the first ⌊|R_k| / η⌋ of R_k;
//     if one of them has no step at rung k+1 yet, promote the best such one to rung k+1.
//   otherwise start a new trial at rung 0 (unless max_trials are started: then wait).
// A trial is promoted as soon as it is in the top 1/η of its rung *as seen so far*, so no
// decision waits for a rung to fill: with `slots` ≥ the thread count every thread stays busy.
// The price (the paper's section 3.2) is that a few trials are promoted that a synchronous
// halving would not have promoted; their number shrinks as rungs grow.
#include <cstddef>

#include "runner/search/search_schedule.hpp"

namespace armfarm::search {

SearchDecision calc_asha_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible);

}  // namespace armfarm::search
