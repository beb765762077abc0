#include "runner/execution/run_headline.hpp"

#include "engine/experiment/metric_catalog.hpp"

#include <cmath>
#include <cstdio>

namespace armfarm {

std::optional<RunHeadline> choose_run_headline(const std::vector<HeadlineJob>& jobs) {
  const MetricInfo* chosen = nullptr;
  int chosen_count = 0;
  for (const MetricInfo& info : metric_catalog()) {
    if (info.kind != MetricKind::result || info.direction == MetricDirection::none) continue;
    int count = 0;
    for (const HeadlineJob& job : jobs) {
      const auto found = job.metrics.find(info.name);
      if (found != job.metrics.end() && std::isfinite(found->second)) ++count;
    }
    if (count > chosen_count) {
      chosen = &info;
      chosen_count = count;
    }
  }
  if (chosen == nullptr) return std::nullopt;
  RunHeadline headline;
  headline.metric = chosen->name;
  headline.direction = to_string(chosen->direction);
  headline.jobs = chosen_count;
  const bool lower_is_better = chosen->direction == MetricDirection::lower;
  bool first = true;
  for (const HeadlineJob& job : jobs) {
    const auto found = job.metrics.find(chosen->name);
    if (found == job.metrics.end() || !std::isfinite(found->second)) continue;
    const double value = found->second;
    const bool better = lower_is_better ? value < headline.best : value > headline.best;
    const bool worse = lower_is_better ? value > headline.worst : value < headline.worst;
    if (first || better) {
      headline.best = value;
      headline.best_label = job.label;
    }
    if (first || worse) {
      headline.worst = value;
      headline.worst_label = job.label;
    }
    first = false;
  }
  return headline;
}

std::string make_headline_text(const RunHeadline& headline) {
  char best[32], worst[32];
  std::snprintf(best, sizeof best, "%.4g", headline.best);
  std::snprintf(worst, sizeof worst, "%.4g", headline.worst);
  return "main metric " + headline.metric + " (" + headline.direction + " is better, " + std::to_string(headline.jobs) +
         (headline.jobs == 1 ? " job" : " jobs") + "): best " + best + " " + headline.best_label + "; worst " + worst +
         " " + headline.worst_label;
}

}  // namespace armfarm
