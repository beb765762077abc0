// The metrics of a job's outcome by name, for tests that look values up.
#pragma once

#include "engine/experiment/job_outcome.hpp"

#include <cmath>
#include <map>
#include <string>

namespace armfarm::testing {

/// Each metric's value (NaN when undefined) under its name, "_j<joint>" appended for a joint
/// metric. A metric scored at several checkpoints keeps its last value.
inline std::map<std::string, double> job_metrics(const JobOutcome& outcome) {
  std::map<std::string, double> metrics;
  for (const Metric& metric : outcome.metrics) {
    metrics[metric.joint ? metric.name + "_j" + std::to_string(*metric.joint) : metric.name] = metric.value.value_or(std::nan(""));
  }
  return metrics;
}

}  // namespace armfarm::testing
