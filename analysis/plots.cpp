#include "analysis/plots.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/search_summary.hpp"
#include "analysis/summary_statistics.hpp"
#include "analysis/table.hpp"
#include "base/config_path.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

namespace armfarm {

PlotKind parse_plot_kind(const std::string& word) {
  for (PlotKind kind : all_plot_kinds()) {
    if (word == to_string(kind)) return kind;
  }
  throw AnalysisError("unknown plot kind '" + word + "' (nmse-vs-kernel, rf-growth, signals, tracking, metric-vs-param, search)");
}

const char* to_string(PlotKind kind) {
  switch (kind) {
    case PlotKind::nmse_vs_kernel: return "nmse-vs-kernel";
    case PlotKind::rf_growth: return "rf-growth";
    case PlotKind::signals: return "signals";
    case PlotKind::tracking: return "tracking";
    case PlotKind::metric_vs_param: return "metric-vs-param";
    case PlotKind::search: return "search";
  }
  return "metric-vs-param";
}

std::vector<PlotKind> all_plot_kinds() {
  return {PlotKind::nmse_vs_kernel, PlotKind::rf_growth, PlotKind::signals, PlotKind::tracking, PlotKind::metric_vs_param,
          PlotKind::search};
}

namespace {

// A parameter's value in a legend or title: a reference to another sweep's job (a two-stage
// sweep's {"params":{"seed":0},"sweep":"x.train"}) reads "seed 0 of x.train", not raw JSON
// wider than the figure; any other value as in the tables.
std::string format_label_value(const nlohmann::json& value) {
  if (!value.is_object() || !value.contains("sweep") || !value["sweep"].is_string()) return format_param_value(value);
  std::string params;
  if (value.contains("params") && value["params"].is_object()) {
    for (const auto& item : value["params"].items()) {
      params += (params.empty() ? "" : ", ") + item.key() + " " + format_param_value(item.value());
    }
  }
  return (params.empty() ? "a job" : params) + " of " + value["sweep"].get<std::string>();
}

// A value with the seed of a referenced job left out, so that the test job of seed s, which
// uses the model of seed s, is a repeat of its configuration and not a configuration of its own.
nlohmann::json without_nested_seed(nlohmann::json value) {
  if (value.is_object() && value.contains("params") && value["params"].is_object()) value["params"].erase("seed");
  return value;
}

}  // namespace

std::string make_short_param_name(const std::string& path) {
  ConfigPath parsed;
  try {
    parsed = parse_config_path(path);
  } catch (const std::invalid_argument&) {
    return path;
  }
  std::size_t last_key = 0;
  for (std::size_t i = 0; i < parsed.size(); ++i) {
    if (!parsed[i].index) last_key = i;
  }
  return ConfigPath(std::vector<PathSegment>(parsed.begin() + static_cast<std::ptrdiff_t>(last_key), parsed.end())).to_string();
}

std::string make_job_label(const JobResult& job) {
  std::string label;
  if (job.params.is_object()) {
    for (const auto& item : job.params.items()) {
      label += (label.empty() ? "" : ", ") + make_short_param_name(item.key()) + "=" + format_label_value(item.value());
    }
  }
  return label.empty() ? job.key.substr(0, 8) : label;
}

namespace {

std::optional<double> as_number(const nlohmann::json& value) {
  if (value.is_number()) return value.get<double>();
  if (value.is_boolean()) return value.get<bool>() ? 1.0 : 0.0;
  return std::nullopt;
}

// "path (unit)" with the unit from the key table (PlotRequest::param_unit); the path alone
// when it has none (dimensionless, a flag or a name).
std::string make_param_axis_label(const PlotRequest& request, const std::string& path) {
  const std::string unit = request.param_unit ? request.param_unit(path) : std::string();
  return unit.empty() ? path : path + " (" + unit + ")";
}

// Whether swept values want a log axis: positive, and either spanning decades or spaced by
// steadier ratios than differences (0.02, 0.05, 0.2 is log-spaced; 1, 2, 3 is not).
bool is_log_spaced(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  if (values.empty() || !(values.front() > 0.0)) return false;
  if (spans_decades(values)) return true;
  if (values.size() < 3 || values.back() / values.front() < 4.0) return false;
  const auto spread = [](const std::vector<double>& steps) {  // coefficient of variation
    double mean = 0, square = 0;
    for (double step : steps) mean += step;
    mean /= static_cast<double>(steps.size());
    for (double step : steps) square += (step - mean) * (step - mean);
    return std::sqrt(square / static_cast<double>(steps.size())) / mean;
  };
  std::vector<double> differences, ratios;
  for (std::size_t i = 1; i < values.size(); ++i) {
    differences.push_back(values[i] - values[i - 1]);
    ratios.push_back(std::log(values[i] / values[i - 1]));
  }
  return spread(ratios) < spread(differences);
}

// The done jobs' values of `metric` by curve and x. A curve is one value of every varying
// parameter other than `x_param` and the seed, so nothing unplotted is pooled.
struct CurvePoints {
  std::string title;
  std::map<double, std::vector<double>> by_x;
};

std::vector<CurvePoints> collect_points(const SweepData& data, const std::string& x_param, const std::string& group_param,
                                        const MetricId& metric) {
  // Only what varies names a curve: a group parameter the sweep holds fixed says nothing.
  std::vector<std::string> split;
  const bool group_varies =
      std::find(data.varying_params.begin(), data.varying_params.end(), group_param) != data.varying_params.end();
  if (!group_param.empty() && group_varies) split.push_back(group_param);
  for (const std::string& path : data.varying_params) {
    if (path != x_param && path != "seed" && path != group_param) split.push_back(path);
  }
  std::vector<CurvePoints> curves;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    const auto x = as_number(find_param_value(job, x_param));
    const auto value = job.metrics.find(metric);
    if (!x || value == job.metrics.end() || !std::isfinite(value->second)) continue;
    std::string title;
    for (const std::string& path : split) {
      title += (title.empty() ? "" : ", ") + make_short_param_name(path) + "=" + format_param_value(find_param_value(job, path));
    }
    auto it = std::find_if(curves.begin(), curves.end(), [&](const CurvePoints& c) { return c.title == title; });
    if (it == curves.end()) it = curves.insert(curves.end(), CurvePoints{title, {}});
    it->by_x[*x].push_back(value->second);
  }
  return curves;
}

// Curves with error bars over the seeds: the mean and its 95 % Student-t interval (the tables'
// cells, analysis/table.hpp). A bar never reaches below zero when no value is negative, and on a
// log axis a bar whose low end is not positive ends on the axis: `panel.y_min`, set below the
// smallest positive end. Points whose mean is not positive cannot sit on a log axis and are left out.
std::vector<Curve> make_error_bar_curves(const std::vector<CurvePoints>& points, bool log_y, const std::string& fallback_title,
                                         Panel& panel) {
  std::vector<Curve> curves;
  bool clipped_at_axis = false;
  double smallest = INFINITY;
  for (const CurvePoints& source : points) {
    Curve curve;
    curve.style = Curve::Style::error_bars;
    curve.title = source.title.empty() ? fallback_title : source.title;
    for (const auto& [x, values] : source.by_x) {
      const SummaryStatistics summary = calc_summary_statistics(values);
      if (log_y && !(summary.mean > 0.0)) continue;
      const bool non_negative = std::all_of(values.begin(), values.end(), [](double v) { return v >= 0.0; });
      double low = summary.ci_low;
      if (non_negative) low = std::max(low, 0.0);
      if (log_y && !(low > 0.0)) {
        low = NAN;  // set to the axis below
        clipped_at_axis = true;
      }
      curve.x.push_back(x);
      curve.y.push_back(summary.mean);
      curve.y_low.push_back(low);
      curve.y_high.push_back(summary.ci_high);
      smallest = std::min(smallest, summary.mean);
      if (low > 0.0) smallest = std::min(smallest, low);
    }
    if (!curve.x.empty()) curves.push_back(std::move(curve));
  }
  if (clipped_at_axis && std::isfinite(smallest)) {
    // Half a decade below the smallest positive end: the clipped bars visibly run into the axis.
    const double axis = smallest / std::sqrt(10.0);
    panel.y_min = panel.y_min ? std::min(*panel.y_min, axis) : axis;
    for (Curve& curve : curves) {
      for (double& low : curve.y_low) {
        if (std::isnan(low)) low = axis;
      }
    }
  }
  // A curve without repeats has no bars to draw: points joined by lines, no caps of zero length.
  for (Curve& curve : curves) {
    bool bars = false;
    for (std::size_t i = 0; i < curve.y.size(); ++i) bars = bars || curve.y_low[i] != curve.y[i] || curve.y_high[i] != curve.y[i];
    if (!bars) curve.style = Curve::Style::lines_points;
  }
  return curves;
}

std::vector<double> all_values(const std::vector<CurvePoints>& points, bool x) {
  std::vector<double> values;
  for (const CurvePoints& curve : points) {
    for (const auto& [at, ys] : curve.by_x) {
      if (x) values.push_back(at);
      else values.insert(values.end(), ys.begin(), ys.end());
    }
  }
  return values;
}

// "jobs not shown: 1 pending, 3 done with tracking_nmse undefined" for the jobs a metric figure
// neither draws nor marks (add_unfinished_marks marks those with an x value); "" when none.
std::string describe_jobs_not_shown(const SweepData& data, const MetricId& metric, const std::string& x_param) {
  std::map<std::string, int> by_status;
  int undefined = 0, absent = 0;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") {
      const bool marked = job.status != "pending" && job.status != "running" && as_number(find_param_value(job, x_param));
      if (!marked) ++by_status[job.status];
      continue;
    }
    const auto value = job.metrics.find(metric);
    if (value == job.metrics.end()) ++absent;
    else if (!std::isfinite(value->second)) ++undefined;
  }
  std::string text;
  for (const auto& [status, count] : by_status) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + status;
  if (undefined > 0) text += (text.empty() ? "" : ", ") + std::to_string(undefined) + " done with " + make_metric_label(metric) + " undefined";
  if (absent > 0) text += (text.empty() ? "" : ", ") + std::to_string(absent) + " done without " + make_metric_label(metric);
  return text.empty() ? "" : "jobs not shown: " + text;
}

std::string describe_error_bars(bool log_y) {
  return std::string("mean, 95 % CI over seeds") + (log_y ? " (clipped at the axis)" : "");
}

// Whether any point of the curves has a bar (more than one seed).
bool has_bars(const std::vector<Curve>& curves) {
  for (const Curve& curve : curves) {
    for (std::size_t i = 0; i < curve.y.size(); ++i) {
      if (curve.y_low[i] != curve.y[i] || curve.y_high[i] != curve.y[i]) return true;
    }
  }
  return false;
}

// The jobs that have an x value but no y value because they did not finish (diverged, failed,
// timeout), as marks on the panel's top edge; "" or the caption's count of them.
std::string add_unfinished_marks(const SweepData& data, const std::string& x_param, Panel& panel) {
  std::map<std::string, int> by_status;
  for (const JobResult& job : data.jobs) {
    if (job.status == "done" || job.status == "pending" || job.status == "running") continue;
    const auto x = as_number(find_param_value(job, x_param));
    if (!x || !std::isfinite(*x) || (panel.log_x && *x <= 0.0)) continue;
    ++by_status[job.status];
    panel.edge_marks_x.push_back(*x);
  }
  std::string text;
  for (const auto& [status, count] : by_status) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + status;
  if (!text.empty()) panel.edge_mark_title = "not finished (" + text + "), at its " + make_short_param_name(x_param);
  return text.empty() ? "" : "marked on the top edge: " + text;
}

std::vector<const JobResult*> choose_jobs(const ResultsStore& store, const SweepData& data,
                                          const std::vector<std::string>& keys, const std::vector<std::string>& series) {
  std::vector<const JobResult*> chosen;
  if (!keys.empty()) {
    for (const std::string& prefix : keys) {
      const JobResult* found = nullptr;
      int matches = 0;
      for (const JobResult& job : data.jobs) {
        if (job.key.compare(0, prefix.size(), prefix) == 0) {
          found = &job;
          ++matches;
        }
      }
      if (matches == 0) throw AnalysisError("sweep '" + data.name + "': no job with key " + prefix);
      if (matches > 1) throw AnalysisError("sweep '" + data.name + "': key prefix " + prefix + " is ambiguous");
      chosen.push_back(found);
    }
    return chosen;
  }
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    const auto names = store.find_series_names(job.id);
    const bool has_all = std::all_of(series.begin(), series.end(), [&](const std::string& name) {
      return std::find(names.begin(), names.end(), name) != names.end();
    });
    if (has_all) chosen.push_back(&job);
  }
  return chosen;
}

// What to set when a plot lacks its series: the key, and an example.
std::string advise_series(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "\"" : ", \"") + name + "\"";
  return "record them with recording.series in the spec, e.g. \"recording\": {\"series\": [" + list + "]}, and run the sweep again";
}

SeriesRecord require_series(const ResultsStore& store, const JobResult& job, const std::string& name) {
  auto series = store.find_series(job.id, name);
  if (!series) throw AnalysisError("job " + job.key + " has no recorded series " + name + " (" + advise_series({name}) + ")");
  return *series;
}

int find_column(const SeriesRecord& series, const std::string& name, int fallback) {
  for (std::size_t i = 0; i < series.columns.size(); ++i) {
    if (series.columns[i] == name) return static_cast<int>(i);
  }
  return fallback < series.rows.cols() ? fallback : -1;
}

Curve make_series_curve(const SeriesRecord& series, int x_column, int y_column, const std::string& title) {
  Curve curve;
  curve.title = title;
  for (Eigen::Index r = 0; r < series.rows.rows(); ++r) {
    curve.x.push_back(series.rows(r, x_column));
    curve.y.push_back(series.rows(r, y_column));
  }
  return curve;
}

// The checkpoints at which jobs recorded `name` (for `joint`, or any joint when empty).
std::set<std::int64_t> find_checkpoints(const SweepData& data, const std::string& name, std::optional<int> joint) {
  std::set<std::int64_t> checkpoints;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) {
      if (id.name == name && id.checkpoint && (!joint || id.joint == joint)) checkpoints.insert(*id.checkpoint);
    }
  }
  return checkpoints;
}

std::string list_checkpoints(const std::set<std::int64_t>& checkpoints) {
  std::string list;
  for (std::int64_t c : checkpoints) list += (list.empty() ? "" : ", ") + std::to_string(c);
  return list;
}

// The nMSE that nmse-vs-kernel draws and at which checkpoint (none for the same-run split).
struct KernelMetric {
  std::string name;
  std::optional<std::int64_t> checkpoint;
  bool last = false;  ///< the checkpoint is the last the sweep recorded
};

KernelMetric choose_kernel_metric(const SweepData& data, const PlotRequest& request) {
  const std::set<std::int64_t> heldout = find_checkpoints(data, "heldout_test_nmse", std::nullopt);
  KernelMetric metric{request.metric, std::nullopt, false};
  if (metric.name.empty()) metric.name = heldout.empty() ? "same_run_test_nmse" : "heldout_test_nmse";
  if (metric.name != "same_run_test_nmse" && metric.name != "heldout_test_nmse") {
    throw AnalysisError("nmse-vs-kernel draws same_run_test_nmse or heldout_test_nmse, not '" + metric.name + "' (metric-vs-param draws any)");
  }
  if (metric.name != "heldout_test_nmse") return metric;
  if (heldout.empty()) throw AnalysisError("sweep '" + data.name + "' has no heldout_test_nmse metric (held-out evaluations)");
  if (request.checkpoint && !heldout.count(*request.checkpoint)) {
    throw AnalysisError("sweep '" + data.name + "': heldout_test_nmse is recorded at checkpoints " + list_checkpoints(heldout) + ", not " +
                        std::to_string(*request.checkpoint) + "; choose one with --checkpoint N");
  }
  metric.checkpoint = request.checkpoint ? *request.checkpoint : *heldout.rbegin();
  metric.last = *metric.checkpoint == *heldout.rbegin();
  return metric;
}

// nmse-vs-kernel's last panel: the receptive fields after training against the kernel width,
// log y where they span decades (unless forced). `log_y` tells the caller which.
Panel make_kernel_fields_panel(const SweepData& data, const PlotRequest& request, const std::string& kernel_label, bool log_x,
                               bool& log_y) {
  Panel fields;
  fields.title = "receptive fields";
  fields.x_label = kernel_label;
  const MetricId metric{"n_receptive_fields", std::nullopt, std::nullopt};
  const auto points = collect_points(data, request.kernel_param, request.adaptation_param, metric);
  log_y = request.log_y.value_or(spans_decades(all_values(points, false)));
  fields.y_label = make_metric_axis_label(data.metric_info, metric);
  fields.log_x = log_x;
  fields.log_y = log_y;
  fields.curves = make_error_bar_curves(points, log_y, "n_receptive_fields", fields);
  add_unfinished_marks(data, request.kernel_param, fields);
  return fields;
}

// Figures 6.1-6.2: the nMSE per joint and the receptive fields against the kernel width. The
// nMSE is the held-out one (heldout_test_nmse, at --checkpoint or the last) where the sweep
// recorded it, the metric `thesis-figure 6.1` draws and issue 23's verdicts use; else the
// training run's same-run split (same_run_test_nmse); --metric chooses.
Figure make_nmse_vs_kernel(const SweepData& data, const PlotRequest& request) {
  const KernelMetric chosen = choose_kernel_metric(data, request);
  const std::string& metric = chosen.name;
  const std::optional<std::int64_t> checkpoint = chosen.checkpoint;
  std::set<int> joints;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) {
      if (id.name == metric && id.joint && id.checkpoint == checkpoint) joints.insert(*id.joint);
    }
  }
  if (joints.empty()) throw AnalysisError("sweep '" + data.name + "' has no " + metric + " metric per joint (batch learning jobs)");
  Figure figure;
  figure.title = "Test nMSE and receptive fields against kernel width (sweep " + data.name + ")";
  figure.caption.push_back(metric == "heldout_test_nmse"
                               ? "nMSE: held-out test nMSE (heldout_test_nmse) at checkpoint " + std::to_string(*checkpoint) +
                                     (chosen.last ? ", the last" : "") + "; receptive fields after training"
                               : "nMSE: same-run test nMSE (same_run_test_nmse, the training run's own test split); receptive fields "
                                 "after training");
  const bool log_x = request.log_x.value_or(true);
  const bool log_y = request.log_y.value_or(true);  // nMSE spans decades across kernel widths
  std::string undefined, marked;
  // The key's last segment: its panels are narrow (two columns at 3.5 in), and the dotted path
  // with "(kernel width, 1/input²)" took three lines of each; the title says "kernel width".
  const std::string kernel_unit = request.param_unit ? request.param_unit(request.kernel_param) : std::string();
  const std::string kernel_label = make_short_param_name(request.kernel_param) + " (" + (kernel_unit.empty() ? "1/input²" : kernel_unit) + ")";
  for (int joint : joints) {
    Panel panel;
    panel.title = "joint " + std::to_string(joint);
    panel.x_label = kernel_label;
    panel.y_label = make_metric_axis_label(data.metric_info, MetricId{metric, std::nullopt, std::nullopt});
    panel.log_x = log_x;
    panel.log_y = log_y;
    panel.curves = make_error_bar_curves(collect_points(data, request.kernel_param, request.adaptation_param,
                                                        MetricId{metric, joint, checkpoint}),
                                         log_y, metric, panel);
    marked = add_unfinished_marks(data, request.kernel_param, panel);
    if (panel.curves.empty()) {
      undefined += (undefined.empty() ? "" : ", ") + std::to_string(joint);  // nMSE undefined (NULL) in every job
      continue;
    }
    figure.panels.push_back(std::move(panel));
  }
  if (figure.panels.empty()) {
    throw AnalysisError("sweep '" + data.name + "': no done job has a defined " + metric + " and a numeric " + request.kernel_param);
  }
  const std::string dropped = describe_jobs_not_shown(data, MetricId{metric, *joints.begin(), checkpoint}, request.kernel_param);
  if (!marked.empty()) figure.caption.push_back(marked);
  if (!dropped.empty()) figure.caption.push_back(dropped);
  if (!undefined.empty()) figure.caption.push_back("joint " + undefined + " not shown: test nMSE undefined in every job (the torque hardly varies)");
  bool fields_log = false;
  Panel fields = make_kernel_fields_panel(data, request, kernel_label, log_x, fields_log);
  bool bars = has_bars(fields.curves);
  for (const Panel& panel : figure.panels) bars = bars || has_bars(panel.curves);
  if (bars) {
    figure.caption.push_back("error bars: " + (log_y == fields_log ? describe_error_bars(log_y)
                                                                   : "nMSE " + describe_error_bars(log_y) + ", receptive fields " +
                                                                         describe_error_bars(fields_log)));
  }
  if (!fields.curves.empty()) figure.panels.push_back(std::move(fields));
  return figure;
}

Figure make_metric_vs_param(const SweepData& data, const PlotRequest& request) {
  if (request.metric.empty() || request.param.empty()) {
    throw AnalysisError("metric-vs-param needs --metric NAME and --param PATH");
  }
  const MetricId metric{request.metric, request.joint, request.checkpoint};
  // A held-out metric exists only at checkpoints: say which to choose.
  const std::set<std::int64_t> checkpoints = find_checkpoints(data, metric.name, metric.joint);
  if (!checkpoints.empty() && (!request.checkpoint || !checkpoints.count(*request.checkpoint))) {
    throw AnalysisError("sweep '" + data.name + "': metric " + metric.name + " is recorded at checkpoints " + list_checkpoints(checkpoints) +
                        (request.checkpoint ? ", not " + std::to_string(*request.checkpoint) : std::string()) +
                        "; choose one with --checkpoint N");
  }
  Panel panel;
  panel.x_label = make_param_axis_label(request, request.param);
  const auto points = collect_points(data, request.param, request.group, metric);
  if (points.empty()) {
    throw AnalysisError("sweep '" + data.name + "': no done job has metric " + make_metric_label(metric) +
                        " and a numeric " + request.param);
  }
  panel.log_x = request.log_x.value_or(is_log_spaced(all_values(points, true)));
  panel.log_y = request.log_y.value_or(spans_decades(all_values(points, false)));
  panel.y_label = make_metric_axis_label(data.metric_info, metric);
  const std::string readable = make_readable_metric_label(metric);
  panel.curves = make_error_bar_curves(points, panel.log_y, readable, panel);
  const std::string marked = add_unfinished_marks(data, request.param, panel);
  Figure figure;
  // One panel: the figure's title says what it draws, in the catalog's words (the column
  // spelling, heldout_test_nmse_j2_c5, is the tables' and the caption's).
  figure.title = readable + " against " + make_short_param_name(request.param) + " (sweep " + data.name + ")";
  figure.caption.push_back("column: " + make_metric_label(metric) + " (the tables' spelling)");
  const std::string dropped = describe_jobs_not_shown(data, metric, request.param);
  if (has_bars(panel.curves)) figure.caption.push_back("error bars: " + describe_error_bars(panel.log_y));
  if (!marked.empty()) figure.caption.push_back(marked);
  if (!dropped.empty()) figure.caption.push_back(dropped);
  figure.panels.push_back(std::move(panel));
  return figure;
}

// A job's label among `jobs`: the parameters that tell them apart ("init_D=0.05"), its key's
// start when none does; for a single job, all its varying parameters (make_job_label). With
// `without_seed` the seed is not one of them (the repeats of a configuration share a label).
std::string make_distinguishing_label(const JobResult& job, const std::vector<const JobResult*>& jobs, bool without_seed = false) {
  if (jobs.size() <= 1) return make_job_label(job);
  std::string label;
  for (const auto& item : job.params.items()) {
    if (without_seed && item.key() == "seed") continue;
    const auto compared = [&](const nlohmann::json& value) { return without_seed ? without_nested_seed(value) : value; };
    const bool differs = std::any_of(jobs.begin(), jobs.end(), [&](const JobResult* other) {
      return compared(find_param_value(*other, item.key())) != compared(item.value());
    });
    const nlohmann::json shown = compared(item.value());
    if (differs) label += (label.empty() ? "" : ", ") + make_short_param_name(item.key()) + "=" + format_label_value(shown);
  }
  return label.empty() && !without_seed ? job.key.substr(0, 8) : label;
}

// The jobs a figure of one curve per job draws: one per group, a group being the repeats
// (seeds) of one configuration, drawn by its first repeat and named by the parameters that
// tell the groups apart ("" when only the seed varies). At most 24 groups (12 colours, then
// dashed) are drawn, so that 60 jobs give 12 legend entries, not 60; `note` says what was left
// out ("" when nothing was).
struct DrawnJobs {
  std::vector<const JobResult*> jobs;
  std::vector<std::string> labels;
  std::string note;
};
constexpr std::size_t kMaxDrawnGroups = 24;
DrawnJobs choose_one_job_per_group(const std::vector<const JobResult*>& jobs) {
  DrawnJobs drawn;
  std::size_t groups = 0, most_repeats = 1;
  std::map<std::string, std::size_t> repeats;
  for (const JobResult* job : jobs) {
    const std::string label = make_distinguishing_label(*job, jobs, /*without_seed=*/true);
    most_repeats = std::max(most_repeats, ++repeats[label]);
    if (repeats[label] > 1) continue;
    ++groups;
    if (drawn.jobs.size() == kMaxDrawnGroups) continue;
    drawn.jobs.push_back(job);
    drawn.labels.push_back(label);
  }
  if (most_repeats > 1) {
    const bool even = std::all_of(repeats.begin(), repeats.end(), [&](const auto& entry) { return entry.second == most_repeats; });
    drawn.note = "its first of " + std::string(even ? "" : "up to ") + std::to_string(most_repeats) + " repeats";
  }
  if (groups > drawn.jobs.size()) {
    drawn.note += std::string(drawn.note.empty() ? "" : "; ") + std::to_string(drawn.jobs.size()) + " of " + std::to_string(groups) +
                  " configurations drawn (--job KEY chooses)";
  }
  if (!drawn.note.empty()) drawn.note = "a curve per configuration: " + drawn.note;
  return drawn;
}

// "j3" (a series column) → "joint 3".
std::string make_joint_title(const std::string& column) {
  const bool numbered = column.size() > 1 && column[0] == 'j' &&
                        std::all_of(column.begin() + 1, column.end(), [](char c) { return c >= '0' && c <= '9'; });
  return numbered ? "joint " + column.substr(1) : column;
}

// The receptive fields of a job per reach, from its TRIAL series (a row per reach: "segment",
// "n_receptive_fields"), when it has more than one reach; else nothing.
std::optional<Curve> make_fields_per_reach(const ResultsStore& store, const JobResult& job, const std::string& title) {
  const auto series = store.find_series(job.id, "TRIAL");
  if (!series || series->rows.rows() < 2) return std::nullopt;
  const int reach = find_column(*series, "segment", -1), fields = find_column(*series, "n_receptive_fields", -1);
  if (reach < 0 || fields < 0 || series->columns[static_cast<std::size_t>(reach)] != "segment" ||
      series->columns[static_cast<std::size_t>(fields)] != "n_receptive_fields") {
    return std::nullopt;
  }
  return make_series_curve(*series, reach, fields, title);
}

// Figure 6.7's kind: the receptive fields of a curve per configuration against the reaches where
// the jobs recorded the TRIAL series over several reaches (the thesis's x axis), else against the
// RF series' time. Log y when the final counts span more than a factor 20 (narrow and wide
// kernels: 4 and 4000 fields), so that the small curves are not squashed onto the x axis.
Figure make_rf_growth(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  std::vector<const JobResult*> jobs;
  bool per_reach = false;
  for (const JobResult* job : choose_jobs(store, data, request.job_keys, {"TRIAL"})) {
    if (make_fields_per_reach(store, *job, "")) jobs.push_back(job);
  }
  if (!jobs.empty() && (request.job_keys.empty() || jobs.size() == request.job_keys.size())) {
    per_reach = true;
  } else {
    jobs = choose_jobs(store, data, request.job_keys, {"RF"});
  }
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the RF series; " + advise_series({"RF"}));
  const auto load = [&](const JobResult& job, const std::string& title) {
    if (per_reach) return *make_fields_per_reach(store, job, title);
    const SeriesRecord series = require_series(store, job, "RF");
    return make_series_curve(series, 0, find_column(series, "n_receptive_fields", static_cast<int>(series.columns.size()) - 1), title);
  };
  if (request.job_keys.empty()) {
    // By default only the jobs whose receptive fields grow while recorded (online learning; a
    // batch model is trained before the recorded pass and stays flat).
    std::vector<const JobResult*> growing;
    for (const JobResult* job : jobs) {
      const Curve curve = load(*job, "");
      if (curve.y.size() > 1 && curve.y.back() != curve.y.front()) growing.push_back(job);
    }
    if (!growing.empty()) jobs = growing;
  }
  Panel panel;
  panel.x_label = "time (s)";
  if (per_reach) {
    panel.x_label = "reaches";
    panel.x_min = 0.0;
  } else {
    const SeriesRecord first = require_series(store, *jobs.front(), "RF");
    if (!first.columns.empty() && first.columns[0] != "t") panel.x_label = first.columns[0];
  }
  const DrawnJobs drawn = choose_one_job_per_group(jobs);
  std::vector<double> finals;
  for (std::size_t i = 0; i < drawn.jobs.size(); ++i) {
    panel.curves.push_back(load(*drawn.jobs[i], drawn.labels[i]));
    if (!panel.curves.back().y.empty()) finals.push_back(panel.curves.back().y.back());
  }
  panel.y_label = "receptive fields (count)";
  panel.tight_x = true;
  panel.log_y = request.log_y.value_or(spans_decades(finals));
  Figure figure;
  figure.title = "Receptive-field growth (sweep " + data.name + ")";
  if (!drawn.note.empty()) figure.caption.push_back(drawn.note);
  std::string scale = panel.log_y ? "; log y: the final counts span more than a factor 20" : "; linear y: the final counts lie within a factor 20";
  if (request.log_y) scale = *request.log_y ? "; log y (--logy)" : "; linear y (--liny)";
  figure.caption.push_back(std::string(per_reach ? "per reach, from the TRIAL series" : "against time, from the RF series") + scale);
  figure.panels.push_back(std::move(panel));
  return figure;
}

// Without --job: a composite job that uses a learner, where feedback and feed-forward both
// mean something; else the first job with the series.
std::vector<const JobResult*> choose_signal_jobs(const ResultsStore& store, const SweepData& data,
                                                 const PlotRequest& request) {
  auto jobs = choose_jobs(store, data, request.job_keys, {"F", "FF"});
  if (!request.job_keys.empty() || jobs.empty()) return jobs;
  for (const JobResult* job : jobs) {
    const nlohmann::json mode = find_param_value(*job, "control.mode");
    const nlohmann::json learning = find_param_value(*job, "learning.mode");
    if (mode == "composite" && learning.is_string() && learning != "none") return {job};
  }
  return {jobs.front()};
}

Figure make_signals(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  const auto jobs = choose_signal_jobs(store, data, request);
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the F and FF series; " + advise_series({"F", "FF", "TOR"}));
  Figure figure;
  // A short title; the job is the caption's (its label took four lines of a paper column).
  figure.title = "Feedback, feed-forward and composite torques (sweep " + data.name + ")";
  if (jobs.size() == 1) figure.caption.push_back("job " + jobs.front()->key.substr(0, 8) + ": " + make_job_label(*jobs.front()));
  // Time series want the page's width: up to four joints stacked in one column.
  for (const JobResult* job : jobs) {
    const SeriesRecord feedback = require_series(store, *job, "F");
    const SeriesRecord feedforward = require_series(store, *job, "FF");
    const auto composite = store.find_series(job->id, "TOR");
    const std::string prefix = jobs.size() > 1 ? make_distinguishing_label(*job, jobs) + ": " : "";
    for (Eigen::Index c = 1; c < feedback.rows.cols(); ++c) {
      const std::size_t p = static_cast<std::size_t>(c - 1);
      if (figure.panels.size() <= p) {
        Panel panel;
        panel.title = make_joint_title(feedback.columns[static_cast<std::size_t>(c)]);
        panel.x_label = "time (s)";
        panel.tight_x = true;
        panel.y_label = "torque (N·m)";
        figure.panels.push_back(std::move(panel));
      }
      Panel& panel = figure.panels[p];
      panel.curves.push_back(make_series_curve(feedback, 0, static_cast<int>(c), prefix + "feedback"));
      if (c < feedforward.rows.cols()) {
        panel.curves.push_back(make_series_curve(feedforward, 0, static_cast<int>(c), prefix + "feed-forward"));
      }
      if (composite && c < composite->rows.cols()) {
        // Under the others, wider: it equals the feedback where the feed-forward is near zero.
        panel.curves.push_back(make_series_curve(*composite, 0, static_cast<int>(c), prefix + "composite"));
        panel.curves.back().underneath = true;
      }
    }
  }
  if (figure.panels.size() <= 4) figure.columns = 1;
  return figure;
}

Figure make_tracking(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  auto jobs = choose_jobs(store, data, request.job_keys, {"POS", "POS_D"});
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the POS and POS_D series; " + advise_series({"POS", "POS_D"}));
  Panel panel;
  panel.title = "end-effector path, y-z plane";
  panel.x_label = "y (m)";
  panel.y_label = "z (m)";
  panel.equal_axes = true;
  const DrawnJobs drawn = choose_one_job_per_group(jobs);
  for (std::size_t i = 0; i < drawn.jobs.size(); ++i) {
    const JobResult* job = drawn.jobs[i];
    const SeriesRecord actual = require_series(store, *job, "POS");
    const nlohmann::json mode = find_param_value(*job, "control.mode");
    std::string title = drawn.labels[i];
    if (mode.is_string() && title.find(mode.get<std::string>()) == std::string::npos) {
      title = mode.get<std::string>() + (title.empty() ? "" : ", " + title);
    }
    if (title.empty()) title = "actual";
    panel.curves.push_back(make_series_curve(actual, find_column(actual, "y", 2), find_column(actual, "z", 3), title));
  }
  // The desired path on top (one per distinct desired path; jobs of one trajectory share it).
  std::vector<std::vector<double>> seen;
  for (const JobResult* job : drawn.jobs) {
    const SeriesRecord desired = require_series(store, *job, "POS_D");
    Curve curve = make_series_curve(desired, find_column(desired, "y", 2), find_column(desired, "z", 3), "desired");
    std::vector<double> signature = curve.x;
    signature.insert(signature.end(), curve.y.begin(), curve.y.end());
    if (std::find(seen.begin(), seen.end(), signature) != seen.end()) continue;
    seen.push_back(signature);
    curve.emphasised = true;
    panel.curves.push_back(std::move(curve));
  }
  Figure figure;
  figure.title = "Tracking (sweep " + data.name + ")";
  if (!drawn.note.empty()) figure.caption.push_back(drawn.note);
  figure.panels.push_back(std::move(panel));
  return figure;
}

Figure make_kind_figure(const ResultsStore& store, const PlotRequest& request) {
  // A search plot spans sweeps (the method beside its random baseline).
  if (request.kind == PlotKind::search) return make_search_figure(store, request.sweep, request.log_y);
  const SweepData data = load_sweep_data(store, choose_sweep(store, request.sweep));
  switch (request.kind) {
    case PlotKind::nmse_vs_kernel: return make_nmse_vs_kernel(data, request);
    case PlotKind::rf_growth: return make_rf_growth(store, data, request);
    case PlotKind::signals: return make_signals(store, data, request);
    case PlotKind::tracking: return make_tracking(store, data, request);
    case PlotKind::metric_vs_param: return make_metric_vs_param(data, request);
    case PlotKind::search: break;
  }
  throw AnalysisError("unknown plot kind");
}

bool have_equal_values(const Curve& a, const Curve& b) {
  return !a.x.empty() && a.x == b.x && a.y == b.y && a.y_low == b.y_low && a.y_high == b.y_high;
}

// "gain_scale=0.2, mode=batch lies under gain_scale=1, mode=batch (equal values) in every
// panel": titled curves of one panel with equal values, which the later one hides (a batch
// model is the same at every gain; the quick start's legend listed a curve no panel showed).
// "" when no curve is hidden. For nmse-vs-kernel and metric-vs-param.
std::string describe_hidden_curves(const Figure& figure) {
  std::vector<std::pair<std::pair<std::string, std::string>, std::vector<std::string>>> hidden;  // (under, over), panels
  for (const Panel& panel : figure.panels) {
    for (std::size_t i = 0; i < panel.curves.size(); ++i) {
      for (std::size_t j = i + 1; j < panel.curves.size(); ++j) {
        const Curve &under = panel.curves[i], &over = panel.curves[j];
        if (under.title.empty() || over.title.empty() || under.title == over.title || !have_equal_values(under, over)) continue;
        const auto pair = std::make_pair(under.title, over.title);
        auto found = std::find_if(hidden.begin(), hidden.end(), [&](const auto& entry) { return entry.first == pair; });
        if (found == hidden.end()) found = hidden.insert(hidden.end(), {pair, {}});
        found->second.push_back(panel.title.empty() ? "the panel" : panel.title);
        break;  // drawn under the first equal curve after it
      }
    }
  }
  std::string text;
  for (const auto& [pair, panels] : hidden) {
    std::string where;
    if (panels.size() == figure.panels.size() && panels.size() > 1) {
      where = "every panel";
    } else {
      for (const std::string& panel : panels) where += (where.empty() ? "" : ", ") + panel;
    }
    text += (text.empty() ? "" : "; ") + pair.first + " lies under " + pair.second + " (equal values) in " + where;
  }
  return text.empty() ? "" : "hidden: " + text;
}

}  // namespace

Figure make_plot_figure(const ResultsStore& store, const PlotRequest& request) {
  Figure figure = make_kind_figure(store, request);
  // The group figures, whose legend names groups (series figures draw one curve per configuration).
  if (request.kind != PlotKind::nmse_vs_kernel && request.kind != PlotKind::metric_vs_param) return figure;
  const std::string hidden = describe_hidden_curves(figure);
  if (!hidden.empty()) figure.caption.push_back(hidden);
  return figure;
}

std::vector<PlotKind> find_available_plot_kinds(const ResultsStore& store, const SweepData& data) {
  std::vector<PlotKind> kinds;
  bool has_test_nmse = false;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) has_test_nmse = has_test_nmse || id.name == "same_run_test_nmse";
  }
  if (has_test_nmse) kinds.push_back(PlotKind::nmse_vs_kernel);
  std::set<std::string> series;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    for (const std::string& name : store.find_series_names(job.id)) series.insert(name);
  }
  // rf-growth draws per reach from TRIAL where a job recorded several reaches (figure 6.7's
  // and the held-out reaching sweep's, which record no RF), else RF against time.
  bool trials = false;
  for (const JobResult& job : data.jobs) {
    if (job.status == "done" && !trials) trials = make_fields_per_reach(store, job, "").has_value();
  }
  if (series.count("RF") || trials) kinds.push_back(PlotKind::rf_growth);
  if (series.count("F") && series.count("FF")) kinds.push_back(PlotKind::signals);
  if (series.count("POS") && series.count("POS_D")) kinds.push_back(PlotKind::tracking);
  if (store.find_search(data.name)) kinds.push_back(PlotKind::search);
  return kinds;
}

}  // namespace armfarm
