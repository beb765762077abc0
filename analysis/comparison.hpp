#pragma once
// Regression checks: two sets of results paired job by job (by what they computed, or by a
// chosen subset of parameters), each metric compared within a
// tolerance, a change outside it judged by the metric's direction of "better" from the
// databases' metric_info. Timing and diagnostic metrics are compared only when asked; a metric
// whose catalog gives no direction is reported as changed, never guessed.
#include "analysis/metric_direction.hpp"
#include "analysis/sweep_data.hpp"

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {

/// |new − base| ≤ atol + rtol·|base| is within tolerance.
struct Tolerance {
  double rtol = 1e-6;
  double atol = 0.0;
  std::optional<BetterDirection> direction;  ///< overrides the metric_info direction
};

/// Tolerances by metric and by (metric, joint), with a default; the most specific applies.
struct ToleranceTable {
  Tolerance defaults;
  std::map<std::string, Tolerance> by_metric;
  std::map<std::pair<std::string, int>, Tolerance> by_metric_joint;
  Tolerance find(const MetricId& metric) const;
};

/// Parses a tolerances file's text:
/// {"default": {"rtol": 0.01, "atol": 0},
///  "metrics": {"tracking_nmse": {"rtol": 0.05, "direction": "lower",
///                                 "joints": {"2": {"atol": 1e-4}}}}}
/// Fields left out inherit from the enclosing level. Throws AnalysisError naming `source` and
/// the JSON path of a bad entry.
ToleranceTable parse_tolerances(const std::string& text, const std::string& source, const Tolerance& defaults);

/// changed: outside tolerance, but metric_info gives no better direction (none or unknown).
enum class ChangeVerdict { within, improved, regressed, changed };

struct MetricComparison {
  std::string key;       ///< the base job's
  std::string next_key;  ///< the new job's (differs from key when pairing by parameters or across recording settings)
  MetricId metric;
  double base = 0.0;
  double next = 0.0;
  double relative_change = 0.0;  ///< (next − base)/|base|; ±inf when base is 0 and next is not
  BetterDirection direction = BetterDirection::unknown;
  bool is_result = true;  ///< false for timing and diagnostic metrics (compared only when asked)
  ChangeVerdict verdict = ChangeVerdict::within;
};

struct StatusChange {
  std::string key;
  std::string base_status;
  std::string next_status;
};

struct ComparisonReport {
  int jobs_paired = 0;
  std::vector<std::string> pair_by;  ///< the pairing parameters; empty: whole configurations less recording
  std::vector<MetricComparison> metrics;     ///< every compared metric of every paired done job
  std::vector<std::string> only_in_base;     ///< keys
  std::vector<std::string> only_in_next;     ///< keys
  std::vector<StatusChange> status_changes;
  std::vector<std::string> missing_metrics;  ///< "key: metric" present in base, absent in new
  /// True when a metric regressed, a base job is missing or no longer done, or a metric vanished.
  bool regressed() const;
};

/// The configuration section that only changes what a job records, never what it computes
/// (series, sampling): its keys never prevent two jobs from pairing.
inline constexpr const char* kRecordingSection = "recording";

/// How compare_results pairs a base job with a new one. `params` empty: jobs pair when their
/// whole configurations, less the recording section, are equal (of several such jobs on one
/// side the first is taken: they computed the same thing; a job without a stored configuration
/// pairs by its key). Otherwise jobs pair when these
/// dotted parameter paths ("control.gain_scale", "seed") have equal values; two jobs of one
/// side with equal values are an error naming the parameters that tell them apart.
struct PairingRule {
  std::vector<std::string> params;
};

/// Compares `next` against `base`. `metric_filter` (names) limits the metrics; `info` (both
/// databases' metric_info) gives directions and kinds; timing and diagnostic metrics are left
/// out unless `include_timing` (and then shown, never gating: their verdict is within or changed).
ComparisonReport compare_results(const std::vector<JobResult>& base, const std::vector<JobResult>& next,
                                 const ToleranceTable& tolerances, const std::vector<std::string>& metric_filter,
                                 const MetricInfoTable& info, bool include_timing = false,
                                 const PairingRule& pairing = {});

/// Markdown (changes outside tolerance, then all compared metrics) or JSON.
std::string format_comparison(const ComparisonReport& report, bool json, bool show_all);

}  // namespace armfarm
