#pragma once
// The thesis's figures for a results database: nMSE and receptive fields against kernel width
// (figures 6.1–6.2), receptive-field growth (6.7), feedback/feed-forward/composite torques
// (6.3, 6.5, 6.8–6.10), end-effector paths in the y–z plane (6.4), and any metric against any
// swept parameter with error bars over repeats.
#include "analysis/figure.hpp"
#include "analysis/sweep_data.hpp"
#include "results/results_store.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

enum class PlotKind { nmse_vs_kernel, rf_growth, signals, tracking, metric_vs_param, search };

/// Parses "nmse-vs-kernel", "rf-growth", "signals", "tracking", "metric-vs-param", "search".
PlotKind parse_plot_kind(const std::string& word);
const char* to_string(PlotKind kind);
/// All kinds, for help texts and reports.
std::vector<PlotKind> all_plot_kinds();

struct PlotRequest {
  PlotKind kind = PlotKind::metric_vs_param;
  std::optional<std::string> sweep;
  std::vector<std::string> job_keys;  ///< full keys or unique prefixes; empty = chosen from the sweep
  std::string metric;                 ///< metric-vs-param; nmse-vs-kernel: same_run_test_nmse or heldout_test_nmse (empty: held-out where recorded)
  std::optional<int> joint;           ///< metric-vs-param: a per-joint metric's joint
  std::optional<std::int64_t> checkpoint;  ///< metric-vs-param, nmse-vs-kernel: a held-out metric's checkpoint (nmse-vs-kernel: default the last)
  std::string param;                  ///< metric-vs-param: x axis
  std::string group;                  ///< metric-vs-param: one curve per value (optional)
  std::string kernel_param = "learning.lwpr.init_D";
  std::string adaptation_param = "learning.lwpr.update_D";
  std::optional<bool> log_x, log_y;   ///< force (true) or forbid (false) log axes; empty = automatic
  /// The SI unit of a configuration key by dotted path ("" for none), for parameter axes. The
  /// runner supplies it from the key table; unset: parameter axes carry no unit.
  std::function<std::string(const std::string& path)> param_unit;
};

/// Builds the figure a request asks for. Axes are logarithmic where the values span decades
/// (nMSE, log-spaced parameters) unless forced; error bars are mean ± std over the seeds on a
/// linear axis and geometric mean ×/÷ geometric std on a log axis (never below zero); swept
/// parameters that are not plotted split the curves instead of being pooled. Throws AnalysisError when the sweep lacks what the
/// kind needs (saying what is missing).
Figure make_plot_figure(const ResultsStore& store, const PlotRequest& request);

/// Which plot kinds a sweep has data for (used by the report).
std::vector<PlotKind> find_available_plot_kinds(const ResultsStore& store, const SweepData& data);

/// A parameter's name in a legend or title: its path from the last key on ("learning.lwpr.init_D"
/// → "init_D", "control.kp[1]" → "kp[1]"), parsed by base/config_path.hpp; the text itself when
/// it is not a path.
std::string make_short_param_name(const std::string& path);

/// A short label of a job from its varying parameters ("init_D=25, gain_scale=0.2").
std::string make_job_label(const JobResult& job);

}  // namespace armfarm
