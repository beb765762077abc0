#include "analysis/search_summary.hpp"

#include "analysis/analysis_error.hpp"
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

Figure make_search_figure(const ResultsStore& store, const std::optional<std::string>& sweep) {
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

  Panel panel;
  panel.title = "Best objective against cost";
  const SearchRecord& first = summaries.front().search;
  panel.x_label = first.budget_unit == "jobs" ? "jobs run (cumulative)" : "estimated CPU-seconds (cumulative)";
  panel.y_label = "best " + first.objective_metric +
                  (first.objective_joint ? " (joint " + std::to_string(*first.objective_joint) + ")" : std::string(" (mean)"));
  double low = 0.0, high = 0.0;
  bool any = false;
  for (const SearchSummary& summary : summaries) {
    if (summary.curve.empty()) continue;
    Curve curve;
    const bool halving = summary.search.method != "random" && summary.search.method != "tpe";
    curve.title = summary.search.method + (halving ? " + " + summary.search.sampler : std::string()) +
                  " (" + summary.search.sweep + ")";
    curve.style = Curve::Style::lines_points;
    for (const SearchCurvePoint& point : summary.curve) {
      // A staircase: the best holds until the next improvement.
      if (!curve.x.empty()) {
        curve.x.push_back(point.cumulative_cost);
        curve.y.push_back(curve.y.back());
      }
      curve.x.push_back(point.cumulative_cost);
      curve.y.push_back(point.best);
      low = any ? std::min(low, point.best) : point.best;
      high = any ? std::max(high, point.best) : point.best;
      any = true;
    }
    curve.x.push_back(summary.spent);
    curve.y.push_back(curve.y.back());
    panel.curves.push_back(std::move(curve));
  }
  if (!any) throw AnalysisError("plot search: no search has an objective at its last rung yet");
  panel.log_y = low > 0.0 && high / low > 100.0;
  Figure figure;
  figure.title = "Search: " + describe_objective(first);
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
