#include "analysis/plots.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/summary_statistics.hpp"
#include "analysis/table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace armfarm {

PlotKind parse_plot_kind(const std::string& word) {
  for (PlotKind kind : all_plot_kinds()) {
    if (word == to_string(kind)) return kind;
  }
  throw AnalysisError("unknown plot kind '" + word + "' (nmse-vs-kernel, rf-growth, signals, tracking, metric-vs-param)");
}

const char* to_string(PlotKind kind) {
  switch (kind) {
    case PlotKind::nmse_vs_kernel: return "nmse-vs-kernel";
    case PlotKind::rf_growth: return "rf-growth";
    case PlotKind::signals: return "signals";
    case PlotKind::tracking: return "tracking";
    case PlotKind::metric_vs_param: return "metric-vs-param";
  }
  return "metric-vs-param";
}

std::vector<PlotKind> all_plot_kinds() {
  return {PlotKind::nmse_vs_kernel, PlotKind::rf_growth, PlotKind::signals, PlotKind::tracking, PlotKind::metric_vs_param};
}

std::string make_job_label(const JobResult& job) {
  std::string label;
  if (job.params.is_object()) {
    for (const auto& item : job.params.items()) {
      std::string name = item.key();
      const auto dot = name.rfind('.');
      if (dot != std::string::npos) name = name.substr(dot + 1);
      label += (label.empty() ? "" : ", ") + name + "=" + format_param_value(item.value());
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

// Mean ± std of a metric over the done jobs of each (group, x) point.
std::vector<Curve> make_grouped_curves(const SweepData& data, const std::string& x_param, const std::string& group_param,
                                       const MetricId& metric, const std::string& group_title_prefix) {
  std::map<std::string, std::map<double, std::vector<double>>> points;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    const auto x = as_number(find_param_value(job, x_param));
    const auto value = job.metrics.find(metric);
    if (!x || value == job.metrics.end() || !std::isfinite(value->second)) continue;
    const std::string group = group_param.empty() ? "" : format_param_value(find_param_value(job, group_param));
    points[group][*x].push_back(value->second);
  }
  std::vector<Curve> curves;
  for (const auto& [group, by_x] : points) {
    Curve curve;
    curve.style = Curve::Style::error_bars;
    curve.title = group_param.empty() ? make_metric_label(metric) : group_title_prefix + group;
    for (const auto& [x, values] : by_x) {
      const SummaryStatistics summary = calc_summary_statistics(values);
      curve.x.push_back(x);
      curve.y.push_back(summary.mean);
      curve.y_error.push_back(summary.std_dev);
    }
    curves.push_back(std::move(curve));
  }
  return curves;
}

std::string last_segment(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
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

SeriesRecord require_series(const ResultsStore& store, const JobResult& job, const std::string& name) {
  auto series = store.find_series(job.id, name);
  if (!series) throw AnalysisError("job " + job.key + " has no recorded series " + name + " (enable it in recording)");
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

Figure make_nmse_vs_kernel(const SweepData& data, const PlotRequest& request) {
  std::set<int> joints;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) {
      if (id.name == "same_run_test_nmse" && id.joint) joints.insert(*id.joint);
    }
  }
  if (joints.empty()) throw AnalysisError("sweep '" + data.name + "' has no same_run_test_nmse metric (batch learning jobs)");
  Figure figure;
  figure.title = "Test nMSE and receptive fields against kernel width (sweep " + data.name + ")";
  const std::string prefix = last_segment(request.adaptation_param) + "=";
  for (int joint : joints) {
    Panel panel;
    panel.title = "joint " + std::to_string(joint);
    panel.x_label = request.kernel_param + " (kernel width, 1/input²)";
    panel.y_label = "test nMSE (dimensionless)";
    panel.log_x = true;
    panel.curves = make_grouped_curves(data, request.kernel_param, request.adaptation_param, MetricId{"same_run_test_nmse", joint}, prefix);
    if (panel.curves.empty()) throw AnalysisError("sweep '" + data.name + "': no numeric " + request.kernel_param + " values");
    figure.panels.push_back(std::move(panel));
  }
  Panel fields;
  fields.title = "receptive fields";
  fields.x_label = request.kernel_param + " (kernel width, 1/input²)";
  fields.y_label = "receptive fields (count)";
  fields.log_x = true;
  fields.curves = make_grouped_curves(data, request.kernel_param, request.adaptation_param, MetricId{"n_receptive_fields", std::nullopt}, prefix);
  if (!fields.curves.empty()) figure.panels.push_back(std::move(fields));
  return figure;
}

Figure make_metric_vs_param(const SweepData& data, const PlotRequest& request) {
  if (request.metric.empty() || request.param.empty()) {
    throw AnalysisError("metric-vs-param needs --metric NAME and --param PATH");
  }
  const MetricId metric{request.metric, request.joint};
  Panel panel;
  panel.title = make_metric_label(metric);
  panel.x_label = request.param;
  panel.y_label = make_metric_label(metric) + " (mean ± std over repeats)";
  panel.curves = make_grouped_curves(data, request.param, request.group, metric, last_segment(request.group) + "=");
  if (panel.curves.empty()) {
    throw AnalysisError("sweep '" + data.name + "': no done job has metric " + make_metric_label(metric) +
                        " and a numeric " + request.param);
  }
  double min_x = INFINITY;
  double max_x = 0.0;
  for (const Curve& curve : panel.curves) {
    for (double x : curve.x) {
      min_x = std::min(min_x, x);
      max_x = std::max(max_x, x);
    }
  }
  panel.log_x = min_x > 0.0 && max_x / min_x >= 100.0;
  Figure figure;
  figure.title = make_metric_label(metric) + " against " + request.param + " (sweep " + data.name + ")";
  figure.panels.push_back(std::move(panel));
  return figure;
}

Figure make_rf_growth(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  const auto jobs = choose_jobs(store, data, request.job_keys, {"RF"});
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the RF series");
  Panel panel;
  panel.title = "receptive fields during learning";
  for (const JobResult* job : jobs) {
    const SeriesRecord series = require_series(store, *job, "RF");
    const int y_column = find_column(series, "n_receptive_fields", static_cast<int>(series.columns.size()) - 1);
    panel.x_label = series.columns.empty() ? "trial" : series.columns[0];
    if (panel.x_label == "t") panel.x_label = "time (s)";
    panel.curves.push_back(make_series_curve(series, 0, y_column, make_job_label(*job)));
  }
  panel.y_label = "receptive fields (count)";
  Figure figure;
  figure.title = "Receptive-field growth (sweep " + data.name + ")";
  figure.panels.push_back(std::move(panel));
  return figure;
}

Figure make_signals(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  auto jobs = choose_jobs(store, data, request.job_keys, {"F", "FF"});
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the F and FF series");
  const JobResult& job = *jobs.front();
  const SeriesRecord feedback = require_series(store, job, "F");
  const SeriesRecord feedforward = require_series(store, job, "FF");
  const auto composite = store.find_series(job.id, "TOR");
  Figure figure;
  figure.title = "Feedback, feed-forward and composite torques: " + make_job_label(job);
  for (Eigen::Index c = 1; c < feedback.rows.cols(); ++c) {
    Panel panel;
    panel.title = feedback.columns[static_cast<std::size_t>(c)];
    panel.x_label = "time (s)";
    panel.y_label = "torque (N·m)";
    panel.curves.push_back(make_series_curve(feedback, 0, static_cast<int>(c), "feedback"));
    if (c < feedforward.rows.cols()) panel.curves.push_back(make_series_curve(feedforward, 0, static_cast<int>(c), "feed-forward"));
    if (composite && c < composite->rows.cols()) panel.curves.push_back(make_series_curve(*composite, 0, static_cast<int>(c), "composite"));
    figure.panels.push_back(std::move(panel));
  }
  return figure;
}

Figure make_tracking(const ResultsStore& store, const SweepData& data, const PlotRequest& request) {
  auto jobs = choose_jobs(store, data, request.job_keys, {"POS", "POS_D"});
  if (jobs.empty()) throw AnalysisError("sweep '" + data.name + "': no done job recorded the POS and POS_D series");
  Panel panel;
  panel.title = "end-effector path, y-z plane";
  panel.x_label = "y (m)";
  panel.y_label = "z (m)";
  panel.equal_axes = true;
  const SeriesRecord desired = require_series(store, *jobs.front(), "POS_D");
  panel.curves.push_back(make_series_curve(desired, find_column(desired, "y", 2), find_column(desired, "z", 3), "desired"));
  for (const JobResult* job : jobs) {
    const SeriesRecord actual = require_series(store, *job, "POS");
    const nlohmann::json mode = find_param_value(*job, "control.mode");
    std::string title = make_job_label(*job);
    if (mode.is_string() && title.find(mode.get<std::string>()) == std::string::npos) title = mode.get<std::string>() + ", " + title;
    panel.curves.push_back(make_series_curve(actual, find_column(actual, "y", 2), find_column(actual, "z", 3), title));
  }
  Figure figure;
  figure.title = "Tracking (sweep " + data.name + ")";
  figure.panels.push_back(std::move(panel));
  return figure;
}

}  // namespace

Figure make_plot_figure(const ResultsStore& store, const PlotRequest& request) {
  const SweepData data = load_sweep_data(store, choose_sweep(store, request.sweep));
  switch (request.kind) {
    case PlotKind::nmse_vs_kernel: return make_nmse_vs_kernel(data, request);
    case PlotKind::rf_growth: return make_rf_growth(store, data, request);
    case PlotKind::signals: return make_signals(store, data, request);
    case PlotKind::tracking: return make_tracking(store, data, request);
    case PlotKind::metric_vs_param: return make_metric_vs_param(data, request);
  }
  throw AnalysisError("unknown plot kind");
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
  if (series.count("RF")) kinds.push_back(PlotKind::rf_growth);
  if (series.count("F") && series.count("FF")) kinds.push_back(PlotKind::signals);
  if (series.count("POS") && series.count("POS_D")) kinds.push_back(PlotKind::tracking);
  return kinds;
}

}  // namespace armfarm
