#pragma once
// A sweep's jobs and their metrics, read once from a results database into plain values that
// the tables, comparisons, plots and reports work on (and that tests can build by hand).
#include "base/config_path.hpp"
#include "results/results_store.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// A metric's identity: its name, for per-joint metrics the 1-based joint number, for
/// held-out evaluations the checkpoint.
struct MetricId {
  std::string name;
  std::optional<int> joint{};
  std::optional<std::int64_t> checkpoint{};
  bool operator<(const MetricId& other) const;
  bool operator==(const MetricId& other) const;
};

/// "name" for a job-level metric, "name_j2" for joint 2, "name_j2_c3" at checkpoint 3: the
/// store's one spelling (make_metric_column_name), also the sweep view's column names.
std::string make_metric_label(const MetricId& id);

/// One job as the analysis sees it.
struct JobResult {
  std::int64_t id = 0;
  std::string key;
  std::string status;   ///< done, failed, diverged, timeout, pending, running
  std::string message;
  std::int64_t seed = 0;
  nlohmann::json params;  ///< the sweep's varying parameters, {"dotted.path": value}
  nlohmann::json config;  ///< the full resolved configuration
  std::map<MetricId, double> metrics;       ///< NaN where the stored value is NULL (undefined)
  std::map<MetricId, std::string> reasons;  ///< the stored reason, where there is one
};

/// The database's `metric_info`, by name.
using MetricInfoTable = std::map<std::string, MetricInfoRecord>;

/// Reads `metric_info` of a store.
MetricInfoTable load_metric_info(const ResultsStore& store);

/// A metric's name as a reader says it: "same_run_test_nmse" → "same-run test nMSE",
/// "n_receptive_fields" → "receptive fields" (acronyms capitalised, "_" as spaces, a count's "n" dropped).
std::string make_readable_metric_name(const std::string& name);

/// A metric as a reader says it, with its joint and checkpoint: "held-out test nMSE, joint 2,
/// checkpoint 5" (titles and legends; make_metric_axis_label adds the unit).
std::string make_readable_metric_label(const MetricId& id);

/// The axis label of a metric: its readable name, the joint and checkpoint, and the unit from
/// the catalog ("feedback absolute mean, joint 2 (N·m)", "receptive fields (count)"); no unit for "1"
/// (dimensionless) or when the catalog lacks the metric.
std::string make_metric_axis_label(const MetricInfoTable& info, const MetricId& id);

struct SweepData {
  std::string name;
  std::vector<std::string> varying_params;  ///< dotted paths, in first-seen order
  std::vector<JobResult> jobs;              ///< in expansion order
  MetricInfoTable metric_info;              ///< what the metric names mean
};

/// The value of a parameter of a job: from its varying params, else from its configuration
/// by dotted path ("control.kp[1]"); null when the configuration has no such element.
nlohmann::json find_param_value(const JobResult& job, const std::string& path);

/// The element of `document` that `path` (a configuration path, base/config_path.hpp: keys and
/// 0-based "[i]") names, or nullptr when it names none or does not parse.
const nlohmann::json* find_config_value(const nlohmann::json& document, const std::string& path);

/// The path of every element of `config` that is not an object (an array is one element: its
/// items are not listed), in key order; none when `config` is not an object.
std::vector<ConfigPath> list_config_leaf_paths(const nlohmann::json& config);

/// The name of the sweep to analyse: `requested` if given (it must exist), else the only
/// sweep of the database. Throws AnalysisError listing the sweeps otherwise.
std::string choose_sweep(const ResultsStore& store, const std::optional<std::string>& requested);

/// Reads a sweep's jobs, params and metrics.
SweepData load_sweep_data(const ResultsStore& store, const std::string& sweep);

/// Makes the varying-parameter list of hand-built data (union of the jobs' params keys).
std::vector<std::string> calc_varying_params(const std::vector<JobResult>& jobs);

}  // namespace armfarm
