#pragma once
// Which way is "better" for a metric, and whether it is a result at all, read from the
// database's `metric_info` (the engine's catalog as the runner wrote it), never guessed from
// the name: what `armfarm compare` uses to tell a regression from an improvement and what
// `merge`, tables and plots use to leave timings out.
#include "analysis/sweep_data.hpp"

#include <string>

namespace armfarm {

enum class BetterDirection {
  lower,    ///< errors: nMSE, RMSE, |feedback|, saturation
  higher,   ///< ff/fb share, simulation speed
  none,     ///< the catalog says neither is better: a change is reported, not judged
  unknown,  ///< the database has no metric_info row for the name
};

/// The direction metric_info gives `name`; unknown without a row.
BetterDirection find_metric_direction(const MetricInfoTable& info, const std::string& name);
/// True unless metric_info gives `name` kind timing or diagnostic (unknown names count as results).
bool is_result_metric(const MetricInfoTable& info, const std::string& name);

/// "lower", "higher", "none", "unknown".
const char* to_string(BetterDirection direction);
/// Parses "lower", "higher", "none"; throws std::invalid_argument otherwise.
BetterDirection parse_better_direction(const std::string& word);

}  // namespace armfarm
