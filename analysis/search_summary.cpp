#include "analysis/search_summary.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/sweep_data.hpp"
#include "base/number_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <map>
#include <sstream>

namespace armfarm {
namespace {

std::string describe_objective(const SearchRecord& search) {
  std::string text = search.objective_metric;
  text += search.objective_joint ? " of joint " + std::to_string(*search.objective_joint) : std::string(" (mean over the joints)");
  if (search.objective_checkpoint) text += " at checkpoint " + std::to_string(*search.objective_checkpoint);
  return text + ", " + search.objective_direction + " is better";
}

std::string describe_rung(const SearchRungSummary& rung) {
  return "rung " + std::to_string(rung.rung) +
         (rung.checkpoint ? " (checkpoint " + std::to_string(*rung.checkpoint) + ")" : std::string(" (whole job)"));
}

}  // namespace

std::optional<SearchSummary> load_search_summary(const ResultsStore& store, const std::string& sweep) {
  std::optional<SearchRecord> search = store.find_search(sweep);
  if (!search) return std::nullopt;
  SearchSummary summary;
  summary.search = *search;
  const bool lower = search->objective_direction != "higher";
  const auto better = [lower](double a, double b) { return lower ? a < b : a > b; };

  std::map<std::int64_t, SearchTrialSummary> trials;
  for (const SearchTrialRecord& trial : store.find_search_trials(sweep)) {
    SearchTrialSummary& entry = trials[trial.trial];
    entry.trial = trial.trial;
    entry.bracket = trial.bracket;
    entry.params = trial.params;
  }
  std::map<std::int64_t, SearchRungSummary> rungs;
  for (const SearchRungRecord& rung : search->rungs) {
    rungs[rung.rung].rung = rung.rung;
    rungs[rung.rung].checkpoint = rung.checkpoint;
  }
  const std::int64_t last_rung = rungs.empty() ? 0 : rungs.rbegin()->first;

  std::optional<double> best;
  for (const SearchStepRecord& step : store.find_search_steps(sweep)) {
    summary.spent += step.cost;
    SearchRungSummary& rung = rungs[step.rung];
    rung.rung = step.rung;
    ++rung.started;
    rung.cost += step.cost;
    SearchTrialSummary& trial = trials[step.trial];
    trial.trial = step.trial;
    trial.cost += step.cost;
    if (!step.committed) continue;
    ++rung.committed;
    summary.committed_cost += step.cost;
    if (!step.objective) {
      ++rung.undefined;
      continue;
    }
    if (step.rung >= trial.rung) {
      trial.rung = step.rung;
      trial.objective = step.objective;
      trial.job_key = step.job_key;
    }
    if (step.rung == last_rung && (!best || better(*step.objective, *best))) {
      best = step.objective;
      summary.curve.push_back({summary.spent, *best, step.step});
    }
  }
  for (auto& [number, trial] : trials) summary.trials.push_back(trial);
  std::stable_sort(summary.trials.begin(), summary.trials.end(),
                   [&better](const SearchTrialSummary& a, const SearchTrialSummary& b) {
                     if (a.objective.has_value() != b.objective.has_value()) return a.objective.has_value();
                     if (a.rung != b.rung) return a.rung > b.rung;
                     if (a.objective && *a.objective != *b.objective) return better(*a.objective, *b.objective);
                     return a.trial < b.trial;
                   });
  for (auto& [number, rung] : rungs) summary.rungs.push_back(rung);
  return summary;
}

std::string format_search_summary(const SearchSummary& summary, std::size_t top) {
  const SearchRecord& search = summary.search;
  std::ostringstream out;
  out << "### Search — sweep " << search.sweep << "\n\n";
  out << "method " << search.method << " (";
  // random and tpe propose every trial themselves; the halving methods draw new ones from `sampler`.
  if (search.method != "random" && search.method != "tpe") out << "sampler " << search.sampler << ", eta " << search.eta << ", ";
  out << "seed " << search.seed;
  out << "); objective " << describe_objective(search) << ".\n";
  out << "budget spent: " << format_number(summary.spent) << " of " << format_number(search.budget) << " "
      << search.budget_unit << " (estimated; " << format_number(summary.committed_cost) << " committed); "
      << summary.trials.size() << " trials.\n\n";

  out << "| rung | checkpoint | started | committed | undefined | survivors | cost |\n";
  out << "|---|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < summary.rungs.size(); ++i) {
    const SearchRungSummary& rung = summary.rungs[i];
    out << "| " << rung.rung << " | " << (rung.checkpoint ? std::to_string(*rung.checkpoint) : std::string("end")) << " | "
        << rung.started << " | " << rung.committed << " | " << rung.undefined << " | "
        << (i + 1 < summary.rungs.size() ? std::to_string(summary.rungs[i + 1].started) : std::string("–")) << " | "
        << format_number(rung.cost) << " |\n";
  }
  out << "\nsurvivors: the steps promoted from the rung (started at the next one).\n\n";

  out << "| rank | trial | rung | objective | cost | key | params |\n";
  out << "|---|---|---|---|---|---|---|\n";
  std::size_t rank = 0;
  for (const SearchTrialSummary& trial : summary.trials) {
    if (rank == top) break;
    ++rank;
    out << "| " << rank << " | " << trial.trial << " | " << (trial.rung >= 0 ? std::to_string(trial.rung) : std::string("–"))
        << " | " << (trial.objective ? format_number(*trial.objective) : std::string("–")) << " | "
        << format_number(trial.cost) << " | " << trial.job_key.substr(0, 12) << " | `" << trial.params << "` |\n";
  }
  if (summary.trials.size() > top) out << "\n(" << summary.trials.size() - top << " more trials not shown)\n";
  out << "\n";
  return out.str();
}

std::string format_search_progress(const SearchSummary& summary) {
  const SearchRecord& search = summary.search;
  std::ostringstream out;
  out << "  search " << search.method
      << (search.method != "random" && search.method != "tpe" ? " (sampler " + search.sampler + ")" : std::string()) << ": " << format_number(summary.spent) << " of "
      << format_number(search.budget) << " " << search.budget_unit << " spent, " << summary.trials.size() << " trials";
  if (!summary.curve.empty()) out << ", best " << format_number(summary.curve.back().best);
  out << "\n";
  for (const SearchRungSummary& rung : summary.rungs) {
    out << "    " << describe_rung(rung) << ": " << rung.started << " started, " << rung.committed << " committed";
    if (rung.undefined > 0) out << " (" << rung.undefined << " without objective)";
    out << "\n";
  }
  return out.str();
}

namespace {

// The searches a search figure draws: every one of the database, or `sweep`'s and every random
// search of the same objective (its baseline).
std::vector<SearchSummary> select_searches(const ResultsStore& store, const std::optional<std::string>& sweep) {
  std::vector<SearchSummary> summaries;
  for (const SweepRecord& record : store.find_sweeps()) {
    if (std::optional<SearchSummary> summary = load_search_summary(store, record.name)) summaries.push_back(std::move(*summary));
  }
  if (sweep) {
    const auto chosen = std::find_if(summaries.begin(), summaries.end(),
                                     [&sweep](const SearchSummary& summary) { return summary.search.sweep == *sweep; });
    if (chosen == summaries.end()) throw AnalysisError("plot search: sweep '" + *sweep + "' has no search");
    const SearchRecord target = chosen->search;
    std::vector<SearchSummary> kept;
    for (SearchSummary& summary : summaries) {
      const SearchRecord& other = summary.search;
      const bool same_objective = other.objective_metric == target.objective_metric &&
                                  other.objective_joint == target.objective_joint &&
                                  other.objective_checkpoint == target.objective_checkpoint;
      if (other.sweep == target.sweep || (other.method == "random" && same_objective)) kept.push_back(std::move(summary));
    }
    summaries = std::move(kept);
  }
  if (summaries.empty()) throw AnalysisError("plot search: the database holds no search");
  return summaries;
}

bool is_baseline(const SearchRecord& search) { return search.method == "random"; }

std::string describe_method(const SearchRecord& search) {
  const bool halving = search.method != "random" && search.method != "tpe";
  return search.method + (halving ? " + " + search.sampler : std::string());
}

// The objective as the catalog names it: "held-out test nMSE, joint 2" (or ", mean over the joints").
MetricId make_objective_id(const SearchRecord& search) {
  return MetricId{search.objective_metric, search.objective_joint, search.objective_checkpoint};
}
std::string describe_readable_objective(const SearchRecord& search) {
  return make_readable_metric_label(make_objective_id(search)) + (search.objective_joint ? "" : ", mean over the joints");
}

// The best objective so far as a staircase (it holds until the next improvement), held to
// the budget spent. A random search, the baseline, is drawn underneath and wider, so that the
// method under test stays visible where it equals the baseline (a TPE search's random start-up
// trials are the random search's own when both have one seed).
Curve make_search_curve(const SearchSummary& summary, const std::string& title) {
  Curve curve;
  curve.title = title;
  curve.style = Curve::Style::lines_points;
  curve.underneath = is_baseline(summary.search);
  for (const SearchCurvePoint& point : summary.curve) {
    if (!curve.x.empty()) {
      curve.x.push_back(point.cumulative_cost);
      curve.y.push_back(curve.y.back());
    }
    curve.x.push_back(point.cumulative_cost);
    curve.y.push_back(point.best);
  }
  curve.x.push_back(summary.spent);
  curve.y.push_back(curve.y.back());
  return curve;
}

// The best of `summary` once `cost` is spent; empty before its first last-rung objective or past its spending.
std::optional<double> find_best_at(const SearchSummary& summary, double cost) {
  if (summary.curve.empty() || cost < summary.curve.front().cumulative_cost || cost > summary.spent) return std::nullopt;
  double best = summary.curve.front().best;
  for (const SearchCurvePoint& point : summary.curve) {
    if (point.cumulative_cost <= cost) best = point.best;
  }
  return best;
}

// The stretches of cost over which two searches' staircases are equal ("from 1 until 7": equal
// from the first and parting at the second; "from 3 to 12": equal to the end of the shorter).
std::string describe_equal_stretches(const SearchSummary& a, const SearchSummary& b) {
  std::vector<double> breaks;
  for (const SearchSummary* summary : {&a, &b}) {
    for (const SearchCurvePoint& point : summary->curve) breaks.push_back(point.cumulative_cost);
    breaks.push_back(summary->spent);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  const double end = std::min(a.spent, b.spent);
  std::string text;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const auto equal_at = [&](std::size_t k) {
      const std::optional<double> x = find_best_at(a, breaks[k]), y = find_best_at(b, breaks[k]);
      return x && y && *x == *y && breaks[k + 1] <= end;
    };
    if (!equal_at(i)) continue;
    std::size_t last = i;
    while (last + 2 < breaks.size() && equal_at(last + 1)) ++last;
    const double to = breaks[last + 1];
    text += (text.empty() ? "from " : ", from ") + format_number(breaks[i]) + (to == end ? " to " : " until ") + format_number(to);
    i = last;
  }
  return text;
}

// "overlap: tpe lies on random (equal values) from 1 until 7 jobs run; …" for every pair of drawn
// searches with equal stretches; "" when none. The one drawn first lies under the other.
std::string describe_search_overlaps(const std::vector<const SearchSummary*>& drawn, const std::vector<Curve>& curves,
                                     const std::string& unit) {
  std::string text;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    for (std::size_t j = i + 1; j < drawn.size(); ++j) {
      const std::string stretches = describe_equal_stretches(*drawn[i], *drawn[j]);
      if (stretches.empty()) continue;
      const bool i_first = curves[i].underneath || !curves[j].underneath;
      const Curve &under = curves[i_first ? i : j], &over = curves[i_first ? j : i];
      text += (text.empty() ? "" : "; ") + over.title + " lies on " + under.title + " (equal values) " + stretches + " " + unit +
              (under.underneath ? ", " + under.title + " the wider line beneath" : std::string(", hiding it"));
    }
  }
  return text.empty() ? "" : "overlap: " + text;
}

}  // namespace

Figure make_search_figure(const ResultsStore& store, const std::optional<std::string>& sweep, std::optional<bool> log_y) {
  const std::vector<SearchSummary> summaries = select_searches(store, sweep);
  const SearchRecord& first = summaries.front().search;
  Panel panel;  // untitled: a single panel sits right under the figure's title
  const std::string unit = first.budget_unit == "jobs" ? "jobs run" : "estimated CPU-seconds";
  panel.x_label = unit + " (cumulative)";
  panel.y_label = "best " + make_metric_axis_label(load_metric_info(store), make_objective_id(first)) +
                  (first.objective_joint ? "" : ", mean over the joints");
  std::vector<const SearchSummary*> drawn;
  for (const SearchSummary& summary : summaries) {
    if (!summary.curve.empty()) drawn.push_back(&summary);
  }
  if (drawn.empty()) throw AnalysisError("plot search: no search has an objective at its last rung yet");
  // The legend names the method; the sweep only where two drawn searches share one.
  std::string sources;
  std::vector<double> bests;
  for (const SearchSummary* summary : drawn) {
    const std::string method = describe_method(summary->search);
    const bool shared = std::count_if(drawn.begin(), drawn.end(), [&](const SearchSummary* other) {
                          return describe_method(other->search) == method;
                        }) > 1;
    panel.curves.push_back(make_search_curve(*summary, shared ? method + " (" + summary->search.sweep + ")" : method));
    sources += (sources.empty() ? "" : "; ") + panel.curves.back().title + ": sweep " + summary->search.sweep +
               (sweep && is_baseline(summary->search) && summary->search.sweep != *sweep ? " (the baseline)" : "");
    bests.insert(bests.end(), panel.curves.back().y.begin(), panel.curves.back().y.end());
  }
  panel.log_y = log_y.value_or(spans_decades(bests));
  Figure figure;
  figure.title = "Search: " + describe_readable_objective(first) + ", " + first.objective_direction + " is better";
  figure.caption.push_back("searches: " + sources);
  figure.caption.push_back("column: " + make_metric_label(make_objective_id(first)) + " (the tables' spelling)");
  const std::string overlaps = describe_search_overlaps(drawn, panel.curves, unit);
  if (!overlaps.empty()) figure.caption.push_back(overlaps);
  figure.panels.push_back(std::move(panel));
  return figure;
}

namespace {

// Mid-ranks, 1-based: a run of tied values takes the mean of the ranks it spans.
std::vector<double> calc_mid_ranks(const std::vector<double>& values) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) ++j;
    const double mid = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) ranks[order[k]] = mid;
    i = j + 1;
  }
  return ranks;
}

}  // namespace

std::optional<double> calc_rank_correlation(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2) return std::nullopt;
  const std::vector<double> r = calc_mid_ranks(x), s = calc_mid_ranks(y);
  const double mean = 0.5 * static_cast<double>(x.size() + 1);  // the mean of any set of mid-ranks of n values
  double sum_rs = 0.0, sum_rr = 0.0, sum_ss = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    sum_rs += (r[i] - mean) * (s[i] - mean);
    sum_rr += (r[i] - mean) * (r[i] - mean);
    sum_ss += (s[i] - mean) * (s[i] - mean);
  }
  if (!(sum_rr > 0.0) || !(sum_ss > 0.0)) return std::nullopt;
  return sum_rs / std::sqrt(sum_rr * sum_ss);
}

}  // namespace armfarm
