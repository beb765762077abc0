#pragma once
// What a search has done, read from its store rows (results/search_store.hpp): the best
// trials, each rung's progress and survivors, the budget spent, and the best objective so far
// against cumulative cost. `armfarm table`, `status`, `plot search` and `report` show it.
//
// A trial's objective is the one of its highest rung with a committed value: rungs stop at
// different learning checkpoints, so a value at a low rung is not compared with one at the
// last rung; trials are ranked by rung (highest first), then by objective in the catalog's
// direction, then by trial number. The curve counts every step's estimated cost in decision
// order and improves only on objectives of the last rung (the objective's own checkpoint).
#include "analysis/figure.hpp"
#include "results/results_store.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct SearchTrialSummary {
  std::int64_t trial = 0;
  std::int64_t bracket = 0;
  std::string params;                   ///< JSON of the trial's point
  std::int64_t rung = -1;               ///< highest rung with a committed objective (-1: none)
  std::optional<double> objective;      ///< its value there
  std::string job_key;                  ///< the job of that step
  double cost = 0.0;                    ///< the trial's steps' estimated cost, summed
};

struct SearchRungSummary {
  std::int64_t rung = 0;
  std::optional<std::int64_t> checkpoint;
  std::int64_t started = 0;    ///< steps decided at this rung
  std::int64_t committed = 0;  ///< of which ended with an objective or a reason
  std::int64_t undefined = 0;  ///< of the committed: no objective (failed, diverged, NULL)
  double cost = 0.0;           ///< the estimated cost of its steps
};

struct SearchCurvePoint {
  double cumulative_cost = 0.0;
  double best = 0.0;  ///< the best last-rung objective up to here
  std::int64_t step = 0;
};

struct SearchSummary {
  SearchRecord search;
  std::vector<SearchTrialSummary> trials;  ///< ranked best first
  std::vector<SearchRungSummary> rungs;    ///< by rung
  double spent = 0.0;                      ///< every step's estimated cost
  double committed_cost = 0.0;             ///< of committed steps only
  std::vector<SearchCurvePoint> curve;     ///< one point per improvement, in step order
};

/// The summary of `sweep`'s search; empty when the sweep has none.
std::optional<SearchSummary> load_search_summary(const ResultsStore& store, const std::string& sweep);

/// Markdown: a heading line with the method, objective and budget spent, the rungs
/// (checkpoint, started, committed, survivors = started at the next rung), and the best
/// `top` trials with their parameters.
std::string format_search_summary(const SearchSummary& summary, std::size_t top = 10);

/// One line per rung for `armfarm status`: "rung 1 (checkpoint 50): 9 started, 7 committed".
std::string format_search_progress(const SearchSummary& summary);

/// `armfarm plot search`: the best last-rung objective so far against cumulative estimated
/// cost, one curve per search. Without `sweep`, every search of the database; with it, that
/// sweep's search and beside it every random search of the same objective (the baseline).
/// The y axis is logarithmic when `log_y` says so, else when the drawn values span decades
/// (spans_decades). Throws AnalysisError when there is no such search or no search has a
/// last-rung objective.
Figure make_search_figure(const ResultsStore& store, const std::optional<std::string>& sweep,
                          std::optional<bool> log_y = std::nullopt);

/// Spearman's rank correlation ρ of the pairs (x[i], y[i]): Pearson's correlation of their
/// ranks, where tied values share the mean of the ranks they span (mid-ranks), so
///   ρ = Σ (r_i − r̄)(s_i − s̄) / √( Σ (r_i − r̄)² · Σ (s_i − s̄)² ).
/// Without ties this equals 1 − 6 Σ d_i² / (n (n² − 1)), d_i = r_i − s_i. How well a search's
/// early rung orders trials as its last rung does (tests/bench/bench_search.cpp measures it on
/// grids). Empty when there are fewer than two pairs, the sizes differ, or either side is
/// constant (a correlation is undefined then).
std::optional<double> calc_rank_correlation(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace armfarm
