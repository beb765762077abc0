#pragma once
// What a search does next, as a pure function of its settings and its history: the schedule of
// trials (new points and promotions to later learning checkpoints), deterministic by construction.
//
// Vocabulary. A *trial* is one point of the space. A *rung* is one of the job's learning
// checkpoints (0-based; the last is the full budget). A *step* is one job: a trial run to a rung,
// either a new trial (at its bracket's first rung) or a promotion (to the next rung). Each step
// has a loss once its job is committed: the objective metric at its rung, signed so that lower is
// better (the catalog's direction), +∞ for a failed or diverged job.
//
// The fixed order of decisions. Step n is decided over the losses of steps 0 … v−1 only, where
//   v = max(v of step n−1, n + 1 − slots),
// raised one step at a time (the runner waiting for that step's job to commit) for as long as
// the method answers "wait" with fewer than n steps visible. `slots` is part of the spec, not
// the thread count: at most `slots` steps are ever undecided-upon, so `-j slots` keeps every
// thread busy, and `-j1`, `-j8`, a resume after `kill -9` and several runners on one database
// all see the same prefix of losses at every decision and so take the same decisions. Each
// step's v is stored with it, so a resumed search can check that it replays the same history.
//
// Costs and the budget. rung_cost[r] estimates a job that runs a trial from scratch to rung r
// (CPU-seconds from the job-cost model, or 1 per job when the budget counts jobs). A promotion
// costs rung_cost[r] − rung_cost[r−1] when it continues from the stored model at rung r−1
// (`resumable`), rung_cost[r] when the job kind must rerun from scratch. A decision whose cost
// would take the spent total past the budget ends the search (pending steps still finish).
//
// Methods:
//   random             each step a new prior point run to the last rung
//   tpe                each step a new TPE point (tpe_sampler.hpp) run to the last rung
//   asha               asynchronous successive halving (asha.hpp); new points from `sampler`
//   successive_halving synchronous brackets of `bracket_size` trials (hyperband.hpp)
//   hyperband          the brackets of Hyperband, each a successive halving (hyperband.hpp)
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "runner/search/search_space.hpp"
#include "runner/search/tpe_sampler.hpp"

namespace armfarm::search {

enum class SearchMethod { random, tpe, asha, successive_halving, hyperband };
/// How asha, successive_halving and hyperband draw their new trials.
enum class SearchSampler { random, tpe };

const char* to_string(SearchMethod method);
const char* to_string(SearchSampler sampler);

struct SearchSettings {
  SearchSpace space;
  SearchMethod method = SearchMethod::random;
  SearchSampler sampler = SearchSampler::random;
  TpeSettings tpe;
  std::uint64_t seed = 1;
  std::size_t eta = 3;              ///< η, the reduction factor between rungs (≥ 2)
  std::size_t slots = 4;            ///< steps that may be in flight (see "The fixed order of decisions")
  std::size_t max_trials = 0;       ///< asha: new trials at most (0: no limit but the budget)
  std::size_t bracket_size = 0;     ///< successive_halving: trials per bracket (0: η^(rungs − 1))
  std::vector<double> rung_cost{1.0};  ///< cost of a job from scratch to each rung (one per rung, increasing)
  bool resumable = true;            ///< a promotion continues from the stored model at the previous rung
  double budget = std::numeric_limits<double>::infinity();  ///< total cost allowed
};

struct SearchTrial {
  SearchPoint point;
  std::size_t bracket = 0;  ///< hyperband / successive_halving: the bracket it belongs to
};

struct SearchStep {
  std::size_t trial = 0;
  std::size_t rung = 0;
  std::size_t visible = 0;  ///< the steps whose losses the decision saw (0 … visible−1)
  double cost = 0.0;        ///< its estimated cost (see "Costs and the budget")
};

struct SearchHistory {
  std::vector<SearchTrial> trials;
  std::vector<SearchStep> steps;
  /// The losses of steps 0 … losses.size()−1 (those committed so far, in step order).
  std::vector<double> losses;
};

struct SearchDecision {
  enum class Kind { run, wait, finished };
  Kind kind = Kind::finished;
  bool new_trial = false;
  std::size_t trial = 0;    ///< the trial to run (new: == trials.size())
  std::size_t rung = 0;     ///< the rung to run it to
  std::size_t bracket = 0;  ///< a new trial's bracket
  SearchPoint point;        ///< a new trial's point
  double cost = 0.0;
};

/// The least visibility of the next step: max(last step's visible, steps + 1 − slots).
std::size_t calc_visible_floor(const SearchSettings& settings, const SearchHistory& history);

/// The next decision seeing the losses of steps 0 … visible−1 (visible ≤ history.losses.size()).
/// "wait": nothing to do until more losses are seen; "finished": the search is over (the budget,
/// the trial limit, or every bracket complete with all losses seen).
SearchDecision calc_next_decision(const SearchSettings& settings, const SearchHistory& history, std::size_t visible);

/// Appends a "run" decision to the history as step `steps.size()` decided with `visible`.
void add_step(const SearchDecision& decision, std::size_t visible, SearchHistory& history);

/// The estimated cost of a step to `rung`: a promotion from rung − 1, or a new trial.
double calc_step_cost(const SearchSettings& settings, bool promotion, std::size_t rung);

/// The cost of all steps so far.
double calc_spent(const SearchHistory& history);

/// Whether steps costing `spent` in all fit `budget`: up to a relative 1e-12, so that a budget
/// of exactly N jobs' cost buys N jobs however the sums round.
bool fits_budget(double spent, double budget);

/// How many whole jobs of `cost` a budget of `budget` buys under fits_budget: what TPE's
/// start-up rule counts (calc_tpe_startup), so that a budget at an exact multiple of the cost
/// gives the same start-up whichever way its division rounds.
double calc_whole_jobs(double budget, double cost);

// Helpers shared by the methods (asha.cpp, hyperband.cpp).

/// The trials with a seen loss at `rung`, best first (lower loss; ties: lower trial number),
/// among trials for which `include(trial)` holds.
std::vector<std::size_t> calc_rung_ranking(const SearchHistory& history, std::size_t visible, std::size_t rung,
                                           const std::function<bool(std::size_t)>& include);
/// Whether trial `trial` has a step (seen or not) at `rung`.
bool has_step(const SearchHistory& history, std::size_t trial, std::size_t rung);
/// A new trial's proposal: from the prior or TPE (settings.sampler, or the method itself),
/// observations from the highest rung with enough seen losses, the rest pending.
SearchPoint calc_new_point(const SearchSettings& settings, const SearchHistory& history, std::size_t visible, bool tpe);

}  // namespace armfarm::search
