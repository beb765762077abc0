#pragma once
// The figure a sweep's end-of-run summary leads with: its main metric and the best and worst
// job by it. The main metric is the first result metric of the engine's catalog
// (engine/experiment/metric_catalog.hpp, which also says which way is better) that has a
// defined job-level value in the most done jobs of the run.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// A done job's job-level metrics (joint and checkpoint empty), defined values only.
struct HeadlineJob {
  std::string label;  ///< make_job_label
  std::map<std::string, double> metrics;
};

struct RunHeadline {
  std::string metric;
  std::string direction;  ///< "lower" or "higher": which way is better
  int jobs = 0;           ///< done jobs with a defined value
  std::string best_label, worst_label;
  double best = 0.0, worst = 0.0;
};

/// None when no done job has a defined result metric with a direction.
std::optional<RunHeadline> choose_run_headline(const std::vector<HeadlineJob>& jobs);

/// "main metric tracking_nmse (lower is better, 12 jobs): best 3f2a1b7c … = 0.00081, worst … = 0.0123".
std::string make_headline_text(const RunHeadline& headline);

}  // namespace armfarm
