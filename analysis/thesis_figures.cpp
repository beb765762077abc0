#include "analysis/thesis_figures.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/summary_statistics.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace armfarm {

const std::vector<std::string>& drawable_thesis_figures() {
  static const std::vector<std::string> numbers = {"6.1", "6.2", "6.7", "6.8", "6.9", "6.10", "6.11", "6.12", "6.13"};
  return numbers;
}

namespace {

using json = nlohmann::json;

const char* const kKernelParam = "learning.lwpr.init_D";
const char* const kAdaptationParam = "learning.lwpr.update_D";

std::string list_drawable() {
  std::string list;
  for (const std::string& number : drawable_thesis_figures()) list += (list.empty() ? "" : ", ") + number;
  return list;
}

const ThesisFigure& find_figure(const ThesisResults& thesis, const std::string& number) {
  for (const ThesisFigure& figure : thesis.figures) {
    if (figure.number == number) return figure;
  }
  throw AnalysisError(thesis.path + ": no figure " + number + " in its `figures`");
}

// "Figure 6.9 (thesis, page 58)" — the page only where the thesis states it; with the caption
// for the figures whose panels do not say what they show.
std::string make_heading(const ThesisFigure& figure, bool with_caption = true) {
  std::string heading = "Figure " + figure.number + " (thesis";
  if (figure.page) heading += ", page " + std::to_string(*figure.page);
  return heading + ")" + (with_caption ? ": " + figure.caption : std::string());
}

// The printed table whose cells give a figure's numbers (its facts' "table": a number such as
// "6.5" or an id such as "fig6_12_numerical").
const ThesisTable& find_figure_table(const ThesisResults& thesis, const ThesisFigure& figure) {
  const json* named = figure.facts.is_object() && figure.facts.contains("table") ? &figure.facts["table"] : nullptr;
  if (!named || !named->is_string()) {
    throw AnalysisError(thesis.path + ": figure " + figure.number + " names no table in its facts (\"table\")");
  }
  const std::string name = named->get<std::string>();
  for (const ThesisTable& table : thesis.tables) {
    if (table.id == name || (table.number && *table.number == name)) return table;
  }
  throw AnalysisError(thesis.path + ": figure " + figure.number + " names table " + name + ", which the file lacks");
}

// The mapping a table's cells share (sweep, where, checkpoint): its first mapped cell's.
ThesisMapping find_table_mapping(const ThesisResults& thesis, const ThesisTable& table) {
  for (const ThesisCell& cell : table.cells) {
    if (cell.mapping.sweep) return cell.mapping;
  }
  throw AnalysisError(thesis.path + ": table " + table.id + " maps no cell to a sweep");
}

std::string require_sweep(const ResultsStore& store, const ThesisResults& thesis, const std::string& figure,
                          const std::optional<std::string>& requested, const std::optional<std::string>& mapped) {
  if (!requested && !mapped) throw AnalysisError(thesis.path + ": figure " + figure + " names no sweep (armfarm.sweep); give --sweep");
  return choose_sweep(store, requested ? requested : mapped);
}

const ComparedCell* find_compared(const ThesisComparison& comparison, const std::string& table, const std::string& row,
                                  const std::string& column) {
  for (const ComparedTable& compared : comparison.tables) {
    if (compared.thesis->id != table) continue;
    for (const ComparedCell& cell : compared.cells) {
      if (cell.thesis->row == row && cell.thesis->column == column) return &cell;
    }
  }
  return nullptr;
}

// The arm joints a job moves (its active_joints), 1..n when it moves every joint of `fallback` n.
std::vector<int> find_active_joints(const JobResult& job, int fallback) {
  std::vector<int> joints;
  const json active = find_param_value(job, "active_joints");
  if (active.is_array()) {
    for (const json& joint : active) {
      if (joint.is_number()) joints.push_back(static_cast<int>(std::lround(joint.get<double>())));
    }
  }
  for (int j = 1; joints.empty() && j <= fallback; ++j) joints.push_back(j);
  return joints;
}

// ------------------------------------------------------------------ figures 6.1 and 6.2
// Both are metric-vs-param figures (plots.hpp) of the kernel-width sweep: one curve per value of
// distance-metric adaptation, 95 % bars over the seeds.

PlotRequest make_kernel_request(const std::string& sweep, const std::string& metric, const ThesisFigureRequest& request) {
  PlotRequest plot;
  plot.kind = PlotKind::metric_vs_param;
  plot.sweep = sweep;
  plot.metric = metric;
  plot.param = kKernelParam;
  plot.group = kAdaptationParam;
  plot.param_unit = request.param_unit;
  return plot;
}

// The kernel figures' x label: the key's last segment and its unit ("learning.lwpr.init_D" ran
// past the right edge under a narrow right-hand panel).
std::string make_kernel_axis_label(const ThesisFigureRequest& request) {
  const std::string unit = request.param_unit ? request.param_unit(kKernelParam) : std::string();
  return make_short_param_name(kKernelParam) + (unit.empty() ? "" : " (" + unit + ")");
}

std::string describe_finding(const ThesisFigure& figure) {
  const json* finding = figure.facts.is_object() && figure.facts.contains("finding") ? &figure.facts["finding"] : nullptr;
  return finding && finding->is_string() ? "thesis's finding (it prints no numbers): " + finding->get<std::string>() : "";
}

// "Figure 6.1 (thesis): nMSE on a test set …" as the first caption paragraph: the thesis's own
// caption, under the figure as in a paper, not in the title over the panels.
std::string make_thesis_caption(const ThesisFigure& figure) { return make_heading(figure); }

// The caption of a composed figure: the thesis's caption, armfarm's source, then the notes of
// its parts (error bars, jobs not shown; each once) and the thesis's finding.
void add_caption(Figure& result, const std::vector<std::string>& notes, const ThesisFigure& figure) {
  for (const std::string& note : notes) {
    if (std::find(result.caption.begin(), result.caption.end(), note) == result.caption.end()) result.caption.push_back(note);
  }
  const std::string finding = describe_finding(figure);
  if (!finding.empty()) result.caption.push_back(finding);
}

Figure make_figure_6_1(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigure& figure,
                       const ThesisFigureRequest& request) {
  const std::string sweep = require_sweep(store, thesis, figure.number, request.sweep, figure.mapping.sweep);
  const SweepData data = load_sweep_data(store, sweep);
  if (data.jobs.empty()) throw AnalysisError("sweep '" + sweep + "' has no jobs");
  const std::vector<int> joints = find_active_joints(data.jobs.front(), 2);
  const std::string metric = "heldout_test_nmse";
  Figure result;
  result.title = "Figure " + figure.number + ": held-out test nMSE against the initial kernel width";
  result.caption.push_back(make_thesis_caption(figure));
  std::vector<std::string> notes;
  std::string missing, checkpoints;
  for (std::size_t k = 0; k < 2 && k < joints.size(); ++k) {
    const int joint = joints[k];
    std::optional<std::int64_t> last;
    for (const JobResult& job : data.jobs) {
      for (const auto& [id, value] : job.metrics) {
        if (id.name == metric && id.joint == joint && id.checkpoint && std::isfinite(value)) last = std::max(last.value_or(0), *id.checkpoint);
      }
    }
    const std::string name = "joint " + std::to_string(k + 1) + " (arm joint " + std::to_string(joint) + ")";
    if (!last) {
      missing += (missing.empty() ? "" : "; ") + name;
      continue;
    }
    PlotRequest plot = make_kernel_request(sweep, metric, request);
    plot.joint = joint;
    plot.checkpoint = last;
    plot.log_y = true;  // nMSE spans decades across kernel widths
    Figure part = make_plot_figure(store, plot);
    for (const std::string& note : part.caption) {
      if (note.rfind("column: ", 0) != 0) notes.push_back(note);
    }
    const std::string at = std::to_string(*last);
    if (checkpoints.find(at) == std::string::npos) checkpoints += (checkpoints.empty() ? "" : ", ") + at;
    for (Panel& panel : part.panels) {
      panel.title = name;
      panel.y_label = "held-out test nMSE";  // the checkpoint is the caption's, the joint the title's
      panel.x_label = make_kernel_axis_label(request);
      result.panels.push_back(std::move(panel));
    }
  }
  if (result.panels.empty()) throw AnalysisError("sweep '" + sweep + "': no done job has a defined " + metric + " on its first two joints");
  result.caption.push_back("armfarm: sweep " + sweep + ", " + metric + " at the last checkpoint (" + checkpoints + ")" +
                           (missing.empty() ? std::string() : "; not drawn, undefined in every job: " + missing));
  add_caption(result, notes, figure);
  return result;
}

Figure make_figure_6_2(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigure& figure,
                       const ThesisFigureRequest& request) {
  const std::string sweep = require_sweep(store, thesis, figure.number, request.sweep, figure.mapping.sweep);
  Figure part = make_plot_figure(store, make_kernel_request(sweep, "n_receptive_fields_per_output", request));
  Figure result;
  result.title = "Figure " + figure.number + ": receptive fields per output against the initial kernel width";
  result.caption.push_back(make_thesis_caption(figure));
  result.caption.push_back("armfarm: sweep " + sweep + ", receptive fields per output after training");
  std::vector<std::string> notes;
  for (const std::string& note : part.caption) {
    if (note.rfind("column: ", 0) != 0) notes.push_back(note);
  }
  add_caption(result, notes, figure);
  result.panels = std::move(part.panels);
  for (Panel& panel : result.panels) panel.x_label = make_kernel_axis_label(request);
  return result;
}

// ------------------------------------------------------------------ figure 6.7

// The thesis's counts after n reaches: facts.receptive_fields_after_reaches {"1": 12, …}.
std::vector<std::pair<double, double>> read_fields_after_reaches(const ThesisFigure& figure) {
  std::vector<std::pair<double, double>> marks;
  const json* counts =
      figure.facts.is_object() && figure.facts.contains("receptive_fields_after_reaches") ? &figure.facts["receptive_fields_after_reaches"] : nullptr;
  if (!counts || !counts->is_object()) return marks;
  for (const auto& item : counts->items()) {
    if (item.value().is_number()) marks.emplace_back(std::stod(item.key()), item.value().get<double>());
  }
  std::sort(marks.begin(), marks.end());
  return marks;
}

std::string format_count(double value) {
  return std::abs(value - std::round(value)) < 1e-9 ? std::to_string(std::llround(value)) : format_table_number(value);
}

// Figure 6.7's groups (every varying parameter but the seed): per reach, the per-output count
// of each seed, from the done jobs' TRIAL series.
struct ReachGroup {
  std::string title;
  bool chosen = false;  ///< passes the figure's `where` (the thesis comparison's setting)
  std::map<double, std::vector<double>> by_reach;
};

struct ReachGroups {
  std::vector<ReachGroup> groups;
  int without_series = 0;  ///< done jobs without the TRIAL series
};

// A job's outputs: the summed count over the per-output count at the end of the run, else its active joints.
double count_outputs(const JobResult& job) {
  const auto summed = job.metrics.find(MetricId{"n_receptive_fields"});
  const auto per_output = job.metrics.find(MetricId{"n_receptive_fields_per_output"});
  if (summed != job.metrics.end() && per_output != job.metrics.end() && per_output->second > 0.0) {
    return std::max(1.0, std::round(summed->second / per_output->second));
  }
  return static_cast<double>(find_active_joints(job, 1).size());
}

ReachGroups collect_reach_groups(const ResultsStore& store, const SweepData& data, const ThesisFigure& figure) {
  ReachGroups result;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    const auto series = store.find_series(job.id, "TRIAL");
    int segment = -1, fields = -1;
    for (std::size_t c = 0; series && c < series->columns.size(); ++c) {
      if (series->columns[c] == "segment") segment = static_cast<int>(c);
      if (series->columns[c] == "n_receptive_fields") fields = static_cast<int>(c);
    }
    if (segment < 0 || fields < 0) {
      ++result.without_series;
      continue;
    }
    const double outputs = count_outputs(job);
    std::string title;
    for (const std::string& path : data.varying_params) {
      if (path == "seed") continue;
      title += (title.empty() ? "" : ", ") + make_short_param_name(path) + "=" + format_param_value(find_param_value(job, path));
    }
    if (title.empty()) title = "armfarm";
    auto& groups = result.groups;
    auto group = std::find_if(groups.begin(), groups.end(), [&](const ReachGroup& g) { return g.title == title; });
    if (group == groups.end()) group = groups.insert(groups.end(), ReachGroup{title, matches_thesis_where(job, figure.mapping), {}});
    for (Eigen::Index r = 0; r < series->rows.rows(); ++r) {
      group->by_reach[series->rows(r, segment)].push_back(series->rows(r, fields) / outputs);
    }
  }
  return result;
}

// What the curves of figure 6.7 leave for its axis and caption.
struct GrowthCurvesSummary {
  double low = INFINITY, high = 0.0;  ///< the final counts (armfarm's means, the thesis's): log axis when they span decades
  double smallest_mean = INFINITY;
  std::string chosen_note;  ///< the comparison's setting's count after the last reach
  int most_seeds = 0;
};

// Per group its mean and, with two seeds or more, its 95 % band (stopping at zero: a count).
void add_growth_curves(const std::vector<ReachGroup>& groups, Panel& panel, GrowthCurvesSummary& summary_out) {
  for (const ReachGroup& group : groups) {
    int seeds = 0;
    Curve mean, band;
    mean.title = band.title = group.title;
    mean.style = Curve::Style::lines;
    band.style = Curve::Style::band;
    for (const auto& [reach, values] : group.by_reach) {
      const SummaryStatistics summary = calc_summary_statistics(values);
      seeds = std::max(seeds, summary.count);
      mean.x.push_back(reach);
      mean.y.push_back(summary.mean);
      mean.y_low.push_back(summary.mean);
      mean.y_high.push_back(summary.mean);
      band.x.push_back(reach);
      band.y.push_back(summary.mean);
      band.y_low.push_back(std::max(summary.ci_low, 0.0));
      band.y_high.push_back(summary.ci_high);
      if (summary.mean > 0.0) summary_out.smallest_mean = std::min(summary_out.smallest_mean, summary.mean);
    }
    if (!mean.y.empty() && mean.y.back() > 0.0) {
      summary_out.low = std::min(summary_out.low, mean.y.back());
      summary_out.high = std::max(summary_out.high, mean.y.back());
    }
    if (group.chosen && !group.by_reach.empty()) {
      const auto& [reach, values] = *group.by_reach.rbegin();
      const SummaryStatistics summary = calc_summary_statistics(values);
      summary_out.chosen_note = "armfarm" + (group.title == "armfarm" ? std::string() : " at " + group.title) +
                                " (the comparison's setting) after " + format_count(reach) + " reaches: " + format_mean_ci(summary, 3) +
                                " (" + std::to_string(summary.count) + ") per output";
    }
    panel.curves.push_back(std::move(mean));
    if (seeds >= 2) panel.curves.push_back(std::move(band));
    summary_out.most_seeds = std::max(summary_out.most_seeds, seeds);
  }
}

// The thesis's counts after 1 / 200 / 1000 reaches: black, dashed, on top, points joined so
// that three marks stand out. Returns the caption's note ("" without counts).
std::string add_thesis_growth_marks(const ThesisFigure& figure, Panel& panel, GrowthCurvesSummary& summary) {
  const auto marks = read_fields_after_reaches(figure);
  if (marks.empty()) return "";
  Curve thesis_marks;
  thesis_marks.style = Curve::Style::lines_points;
  thesis_marks.emphasised = true;
  std::string counts, reaches;
  for (const auto& [reach, count] : marks) {
    thesis_marks.x.push_back(reach);
    thesis_marks.y.push_back(count);
    counts += (counts.empty() ? "" : " / ") + format_count(count);
    reaches += (reaches.empty() ? "" : " / ") + format_count(reach);
  }
  summary.low = std::min(summary.low, marks.back().second);
  summary.high = std::max(summary.high, marks.back().second);
  thesis_marks.title = "thesis: " + counts;  // short: a long entry ran past the page's edge
  panel.curves.push_back(std::move(thesis_marks));
  return "thesis (black marks, dashed): " + counts + " receptive fields after " + reaches + " reaches";
}

// Log y when the final counts span more than a factor 20; a band's low end at or below zero then
// ends on the axis, half a decade below the smallest mean.
void choose_growth_scale(Panel& panel, const GrowthCurvesSummary& summary) {
  panel.log_y = summary.low > 0.0 && summary.high / summary.low >= 20.0;
  if (!panel.log_y || !std::isfinite(summary.smallest_mean)) return;
  const double axis = summary.smallest_mean / std::sqrt(10.0);
  panel.y_min = axis;
  for (Curve& curve : panel.curves) {
    for (double& end : curve.y_low) end = std::max(end, axis);
  }
}

Figure make_figure_6_7(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigure& figure,
                       const ThesisFigureRequest& request) {
  const std::string sweep = require_sweep(store, thesis, figure.number, request.sweep, figure.mapping.sweep);
  const ReachGroups groups = collect_reach_groups(store, load_sweep_data(store, sweep), figure);
  if (groups.groups.empty()) {
    throw AnalysisError("sweep '" + sweep + "': no done job recorded the TRIAL series (record it with recording.series, e.g. "
                        "\"recording\": {\"series\": [\"TRIAL\"]}, and run the sweep again)");
  }
  Panel panel;
  panel.x_label = "reaches";
  panel.y_label = "receptive fields per output (count)";
  panel.tight_x = true;
  GrowthCurvesSummary summary;
  add_growth_curves(groups.groups, panel, summary);
  const std::string thesis_note = add_thesis_growth_marks(figure, panel, summary);
  choose_growth_scale(panel, summary);
  panel.x_min = 0.0;  // 0 reaches: the axis starts before the first
  Figure result;
  result.title = "Figure " + figure.number + ": receptive fields per output against reaches";
  result.caption.push_back(make_thesis_caption(figure));
  result.caption.push_back("armfarm: sweep " + sweep + ", the TRIAL series' count per reach ÷ the outputs; " +
                           (summary.most_seeds >= 2 ? "mean and 95 % band over the seeds" : "one seed, no band") +
                           (panel.log_y ? "; log y: the counts span more than a factor 20" : ""));
  if (!summary.chosen_note.empty()) result.caption.push_back(summary.chosen_note);
  if (!thesis_note.empty()) result.caption.push_back(thesis_note);
  if (groups.without_series > 0) {
    result.caption.push_back("jobs not shown: " + std::to_string(groups.without_series) + " done without the TRIAL series");
  }
  result.panels.push_back(std::move(panel));
  return result;
}

// ------------------------------------------------------------------ signals: 6.8–6.10, 6.12, 6.13

struct SignalSource {
  const JobResult* job = nullptr;
  SeriesRecord feedback, feed_forward;
  std::optional<SeriesRecord> composite;
};

std::vector<std::string> make_signal_names(const ThesisMapping& mapping) {
  std::vector<std::string> names = {"F", "FF", "TOR"};
  if (mapping.checkpoint) {
    const std::string suffix = "_c" + std::to_string(std::llround(*mapping.checkpoint));
    for (std::string& name : names) name = "heldout_" + name + suffix;
  }
  return names;
}

std::string advise_signal_recording(const ThesisMapping& mapping) {
  const std::string prefix = mapping.checkpoint ? "heldout_" : "";
  return "record them with recording.series, e.g. \"recording\": {\"series\": [\"TRIAL\", \"" + prefix + "F\", \"" + prefix + "FF\", \"" +
         prefix + "TOR\"]}, and run the sweep again";
}

// The job a signal figure draws: the requested one, else the done job passing the mapping's
// filter with the lowest seed that recorded the series.
SignalSource choose_signal_source(const ResultsStore& store, const SweepData& data, const ThesisMapping& mapping,
                                  const std::vector<std::string>& keys) {
  const std::vector<std::string> names = make_signal_names(mapping);
  std::vector<const JobResult*> candidates;
  for (const JobResult& job : data.jobs) {
    if (!keys.empty()) {
      if (std::any_of(keys.begin(), keys.end(), [&](const std::string& key) { return job.key.compare(0, key.size(), key) == 0; })) {
        candidates.push_back(&job);
      }
    } else if (job.status == "done" && matches_thesis_where(job, mapping)) {
      candidates.push_back(&job);
    }
  }
  if (!keys.empty() && candidates.size() != 1) {
    throw AnalysisError("sweep '" + data.name + "': --job matches " + std::to_string(candidates.size()) + " jobs, give one key (or unique prefix)");
  }
  std::sort(candidates.begin(), candidates.end(), [](const JobResult* a, const JobResult* b) { return a->seed < b->seed; });
  for (const JobResult* job : candidates) {
    auto feedback = store.find_series(job->id, names[0]);
    auto feed_forward = store.find_series(job->id, names[1]);
    if (!feedback || !feed_forward) continue;
    return SignalSource{job, *feedback, *feed_forward, store.find_series(job->id, names[2])};
  }
  throw AnalysisError("sweep '" + data.name + "': no " + (keys.empty() ? "done job passing the figure's filter" : "chosen job") +
                      " recorded the series " + names[0] + " and " + names[1] + "; " + advise_signal_recording(mapping));
}

Curve make_column_curve(const SeriesRecord& series, Eigen::Index column, const std::string& title) {
  Curve curve;
  curve.title = title;
  for (Eigen::Index r = 0; r < series.rows.rows(); ++r) {
    curve.x.push_back(series.rows(r, 0));
    curve.y.push_back(series.rows(r, column));
  }
  return curve;
}

// The caption's lines on a signal figure's source: the sweep, job and pass drawn, then the
// model's receptive fields (per output and summed) beside the thesis's count, which it does not
// say is either.
std::vector<std::string> describe_signal_source(const SignalSource& source, const ThesisFigure& figure, const ThesisMapping& mapping,
                                                const std::string& sweep) {
  std::vector<std::string> lines;
  std::string source_line = "armfarm: sweep " + sweep + ", job " + source.job->key.substr(0, 8) + " (seed " + std::to_string(source.job->seed) + ")";
  std::optional<std::int64_t> checkpoint;
  if (mapping.checkpoint) {
    checkpoint = std::llround(*mapping.checkpoint);
    source_line += ", the held-out pass after " + std::to_string(*checkpoint) + (*checkpoint == 1 ? " reach" : " reaches");
  } else {
    source_line += ", the test pass over the recording";
  }
  lines.push_back(source_line);
  // The model's receptive fields beside the thesis's count (which it does not say is per output or summed).
  const std::string prefix = checkpoint ? "heldout_" : "";
  const auto per_output = source.job->metrics.find(MetricId{prefix + "n_receptive_fields_per_output", std::nullopt, checkpoint});
  const auto summed = source.job->metrics.find(MetricId{prefix + "n_receptive_fields", std::nullopt, checkpoint});
  std::string fields;
  if (per_output != source.job->metrics.end() && std::isfinite(per_output->second)) fields = format_count(per_output->second) + " per output";
  if (summed != source.job->metrics.end() && std::isfinite(summed->second)) {
    fields += (fields.empty() ? "" : ", ") + format_count(summed->second) + " summed over the outputs";
  }
  const json* thesis_fields = figure.facts.is_object() ? (figure.facts.contains("receptive_fields") ? &figure.facts["receptive_fields"]
                                                          : figure.facts.contains("model_receptive_fields") ? &figure.facts["model_receptive_fields"]
                                                                                                             : nullptr)
                                                        : nullptr;
  if (!fields.empty() || (thesis_fields && thesis_fields->is_number())) {
    lines.push_back("receptive fields of the model: armfarm " + (fields.empty() ? std::string("not recorded") : fields) +
                             (thesis_fields && thesis_fields->is_number() ? "; thesis " + format_count(thesis_fields->get<double>()) : std::string()));
  }
  return lines;
}

Figure make_signal_figure(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigure& figure,
                          const ThesisFigureRequest& request, bool with_composite) {
  const ThesisTable& table = find_figure_table(thesis, figure);
  ThesisMapping mapping = find_table_mapping(thesis, table);
  if (figure.mapping.checkpoint) mapping.checkpoint = figure.mapping.checkpoint;
  const std::string sweep = require_sweep(store, thesis, figure.number, request.sweep, mapping.sweep);
  const SweepData data = load_sweep_data(store, sweep);
  const SignalSource source = choose_signal_source(store, data, mapping, request.job_keys);
  const ThesisComparison comparison = make_thesis_comparison(thesis, store, Aggregate::mean, mapping.sweep);
  const std::vector<int> joints = find_active_joints(*source.job, static_cast<int>(source.feedback.rows.cols()) - 1);
  Figure result;
  // The title says what is drawn; the source, the model's size and the comparison go under the
  // figure (a caption and a table), so the panels keep their room at paper width. Stacked in one
  // column, full width: the torques are time series.
  result.title = make_heading(figure, false) + (with_composite ? ": feedback, feed-forward and composite torque" : ": feedback and feed-forward torque");
  result.columns = 1;
  if (!figure.caption.empty()) {
    result.caption.push_back(make_thesis_caption(figure));
    // The thesis's caption names its own colours; armfarm's are the legend's.
    result.caption.push_back("the colours the thesis's caption names are its own; armfarm's are in the legend");
  }
  for (std::string& line : describe_signal_source(source, figure, mapping, sweep)) result.caption.push_back(std::move(line));
  const std::string table_name = table.number ? "table " + *table.number : table.id;
  result.table.header = {"joint", "thesis", "armfarm [95 % CI]", "n", "verdict"};
  for (Eigen::Index c = 1; c < source.feedback.rows.cols(); ++c) {
    const int k = static_cast<int>(c);  // the thesis's "Joint k"
    Panel panel;
    panel.title = "joint " + std::to_string(k);
    if (static_cast<std::size_t>(k) <= joints.size()) panel.title += " (arm " + std::to_string(joints[static_cast<std::size_t>(k - 1)]) + ")";
    if (const ComparedCell* cell = find_compared(comparison, table.id, "Joint " + std::to_string(k), "avg(ff/fb)")) {
      const bool compared = cell->state == CellState::compared;
      const bool judged = cell->verdict != Verdict::none && cell->verdict != Verdict::one_seed;
      result.table.rows.push_back({std::to_string(k), format_table_number(cell->thesis->value), compared ? format_mean_ci(cell->armfarm, 3) : "not run",
                                   compared ? std::to_string(cell->armfarm.count) : "", judged ? to_string(cell->verdict) : "–"});
    }
    panel.x_label = "time (s)";
    panel.y_label = "torque (N·m)";
    panel.tight_x = true;
    panel.curves.push_back(make_column_curve(source.feedback, c, "feedback"));
    if (c < source.feed_forward.rows.cols()) panel.curves.push_back(make_column_curve(source.feed_forward, c, "feed-forward"));
    if (with_composite && source.composite && c < source.composite->rows.cols()) {
      // The sum of the two, drawn under them and wider: where the feed-forward is near zero
      // (joint 1 after one reach) it is the feedback, which it hid when drawn on top.
      panel.curves.push_back(make_column_curve(*source.composite, c, "composite"));
      panel.curves.back().underneath = true;
    }
    result.panels.push_back(std::move(panel));
  }
  if (result.table.rows.empty()) {
    result.table = {};
  } else {
    result.caption.push_back("table: avg(ff/fb) per joint, the thesis's (" + table_name + ") and armfarm's mean [95 % CI] over n seeds; "
                             "verdicts by sweeps/thesis/README.md");
  }
  return result;
}

// ------------------------------------------------------------------ figure 6.11

Figure make_figure_6_11(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigure& figure,
                        const ThesisFigureRequest& request) {
  Figure result;
  result.title = "Figure " + figure.number + ": the two recordings' desired paths";
  result.caption.push_back(make_thesis_caption(figure));
  std::string files;
  for (const char* number : {"6.12", "6.13"}) {
    const ThesisFigure& task = find_figure(thesis, number);
    const ThesisMapping mapping = find_table_mapping(thesis, find_figure_table(thesis, task));
    const std::string sweep = require_sweep(store, thesis, figure.number, request.sweep, mapping.sweep);
    const SweepData data = load_sweep_data(store, sweep);
    const JobResult* chosen = nullptr;
    std::optional<SeriesRecord> path;
    for (const JobResult& job : data.jobs) {
      if (job.status != "done" || !matches_thesis_where(job, mapping)) continue;
      path = store.find_series(job.id, "POS_D");
      if (path) {
        chosen = &job;
        break;
      }
    }
    if (!chosen) {
      throw AnalysisError("sweep '" + sweep + "': no done job of figure " + number +
                          " recorded POS_D (record it with recording.series, e.g. \"recording\": {\"series\": [\"TRIAL\", \"POS_D\"]}, "
                          "and run the sweep again)");
    }
    std::string name = number == std::string("6.12") ? "picking" : "sphere";
    for (const auto& [path_key, value] : mapping.where) {
      if (value.is_string()) name = value.get<std::string>();
    }
    const auto slash = name.rfind('/');
    if (slash != std::string::npos) name = name.substr(slash + 1);
    files += (files.empty() ? "" : " and ") + name + " (figure " + number + ")";
    // The panel titles name the task alone: a file name over a narrow panel ran past the page.
    const std::string task_name = number == std::string("6.12") ? "picking" : "sphere";
    static const std::tuple<int, int, const char*> kViews[] = {{1, 2, "(x-y)"}, {2, 3, "(y-z)"}};
    for (const auto& [first, second, view] : kViews) {
      Panel panel;
      static const char* const axes[] = {"t", "x", "y", "z"};
      panel.title = task_name + " " + view;
      panel.x_label = std::string(axes[first]) + " (m)";
      panel.y_label = std::string(axes[second]) + " (m)";
      panel.equal_axes = true;
      Curve curve;
      curve.title = name;
      for (Eigen::Index r = 0; r < path->rows.rows(); ++r) {
        curve.x.push_back(path->rows(r, first));
        curve.y.push_back(path->rows(r, second));
      }
      panel.curves.push_back(std::move(curve));
      result.panels.push_back(std::move(panel));
    }
  }
  result.caption.push_back("armfarm: the desired end-effector path (POS_D) of the test jobs of " + files +
                           ", synthetic stand-ins for the thesis's recordings; a row per recording, left its top view (x-y), right its side view (y-z)");
  return result;
}

}  // namespace

Figure make_thesis_figure(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigureRequest& request) {
  const auto& drawable = drawable_thesis_figures();
  if (std::find(drawable.begin(), drawable.end(), request.number) == drawable.end()) {
    throw AnalysisError("thesis-figure: figure '" + request.number + "' is not drawn (drawn: " + list_drawable() + ")");
  }
  const ThesisFigure& figure = find_figure(thesis, request.number);
  if (request.number == "6.1") return make_figure_6_1(store, thesis, figure, request);
  if (request.number == "6.2") return make_figure_6_2(store, thesis, figure, request);
  if (request.number == "6.7") return make_figure_6_7(store, thesis, figure, request);
  if (request.number == "6.11") return make_figure_6_11(store, thesis, figure, request);
  const bool with_composite = request.number == "6.8" || request.number == "6.9" || request.number == "6.10";
  return make_signal_figure(store, thesis, figure, request, with_composite);
}

}  // namespace armfarm
