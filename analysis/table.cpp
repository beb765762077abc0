#include "analysis/table.hpp"

#include "analysis/analysis_error.hpp"
#include "base/config_path.hpp"
#include "base/number_format.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace armfarm {

TableFormat parse_table_format(const std::string& word) {
  if (word == "md" || word == "markdown") return TableFormat::markdown;
  if (word == "csv") return TableFormat::csv;
  if (word == "latex") return TableFormat::latex;
  if (word == "json") return TableFormat::json;
  throw std::invalid_argument("--format must be md, csv, latex or json, not '" + word + "'");
}

std::string format_param_value(const nlohmann::json& value) {
  if (value.is_null()) return "-";
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  if (value.is_number_integer() || value.is_number_unsigned()) return value.dump();
  if (value.is_number()) return format_table_number(value.get<double>());
  return value.dump();
}

namespace {

bool param_matches(const nlohmann::json& value, const std::string& wanted) {
  if (format_param_value(value) == wanted || value.dump() == wanted) return true;
  if (value.is_number()) {
    try {
      std::size_t used = 0;
      const double number = std::stod(wanted, &used);
      return used == wanted.size() && number == value.get<double>();
    } catch (const std::exception&) {
      return false;
    }
  }
  return false;
}

bool is_finished_badly(const std::string& status) {
  return status == "failed" || status == "diverged" || status == "timeout";
}

}  // namespace

NameMatch make_param_name_match(const std::string& word) { return NameMatch{calc_typo_limit(word), false, true}; }

namespace {

std::string make_suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  const auto nearest = find_closest_name(word, candidates, make_param_name_match(word));
  return nearest ? "; did you mean '" + *nearest + "'?" : "";
}

std::vector<std::string> list_param_candidates(const SweepData& data) {
  std::vector<std::string> candidates = data.varying_params;
  // Every path of a job's configuration down to its values (not into arrays), printed.
  if (!data.jobs.empty()) {
    for (const ConfigPath& path : list_config_leaf_paths(data.jobs.front().config)) candidates.push_back(path.to_string());
  }
  return candidates;
}

void check_param_known(const SweepData& data, const std::string& path, const std::string& option) {
  const bool known = std::any_of(data.jobs.begin(), data.jobs.end(),
                                 [&](const JobResult& job) { return !find_param_value(job, path).is_null(); });
  if (!known) {
    std::string varying;
    for (const std::string& p : data.varying_params) varying += (varying.empty() ? "" : ", ") + p;
    throw AnalysisError("sweep '" + data.name + "': " + option + ": no parameter '" + path + "'" +
                        make_suggestion(path, list_param_candidates(data)) +
                        (varying.empty() ? "" : " (varying: " + varying + ")"));
  }
}

}  // namespace

namespace {

bool is_dimension(const std::string& row) { return row == "joint" || row == "checkpoint"; }

bool has_row(const TableSpec& spec, const std::string& row) {
  return std::find(spec.rows.begin(), spec.rows.end(), row) != spec.rows.end();
}

bool is_joint_wanted(const TableSpec& spec, int joint) {
  return spec.joints.empty() || std::find(spec.joints.begin(), spec.joints.end(), joint) != spec.joints.end();
}

/// The --where and --rows parameters name something in the sweep; checkpoint rows need checkpoints.
void check_table_rows(const SweepData& data, const TableSpec& spec) {
  for (const auto& [path, wanted] : spec.where) check_param_known(data, path, "--where");
  for (const std::string& row : spec.rows) {
    if (!is_dimension(row)) check_param_known(data, row, "--rows");
  }
  if (has_row(spec, "checkpoint")) {
    const bool any_checkpoint = std::any_of(data.jobs.begin(), data.jobs.end(), [](const JobResult& job) {
      return std::any_of(job.metrics.begin(), job.metrics.end(), [](const auto& item) { return item.first.checkpoint.has_value(); });
    });
    if (!any_checkpoint) {
      throw AnalysisError("sweep '" + data.name + "': --rows checkpoint: the sweep has no checkpointed (heldout_*) metrics; " +
                          "set learning.heldout_checkpoints to evaluate held-out checkpoints");
    }
  }
}

/// Jobs kept by --where.
std::vector<const JobResult*> select_table_jobs(const SweepData& data, const TableSpec& spec) {
  std::vector<const JobResult*> jobs;
  for (const JobResult& job : data.jobs) {
    bool keep = true;
    for (const auto& [path, wanted] : spec.where) {
      if (!param_matches(find_param_value(job, path), wanted)) keep = false;
    }
    if (keep) jobs.push_back(&job);
  }
  return jobs;
}

/// Which metric ids the kept jobs have, per name: their joints (none: job level) and checkpoints.
struct MetricShapes {
  std::map<std::string, std::set<std::optional<int>>> joints_by_name;
  std::map<std::string, std::set<std::int64_t>> checkpoints_by_name;
};

MetricShapes find_metric_shapes(const std::vector<const JobResult*>& jobs) {
  MetricShapes shapes;
  for (const JobResult* job : jobs) {
    for (const auto& [id, value] : job->metrics) {
      shapes.joints_by_name[id.name].insert(id.joint);
      if (id.checkpoint) shapes.checkpoints_by_name[id.name].insert(*id.checkpoint);
    }
  }
  return shapes;
}

/// Every metric name of the sweep, in order of first appearance.
std::vector<std::string> list_metric_names(const SweepData& data) {
  std::vector<std::string> all_names;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) {
      if (std::find(all_names.begin(), all_names.end(), id.name) == all_names.end()) all_names.push_back(id.name);
    }
  }
  return all_names;
}

/// The columns of metric `name`: one per checkpoint (unless checkpoints are rows), each
/// job-level, from the row's joint, or one per wanted joint.
void add_metric_columns(const TableSpec& spec, const std::string& name, const std::set<std::optional<int>>& joints,
                        const std::set<std::int64_t>* checkpoints, Table& table) {
  const bool joint_rows = has_row(spec, "joint");
  const bool checkpoint_rows = has_row(spec, "checkpoint");
  const bool has_job_level = joints.count(std::nullopt) > 0;
  const bool has_joints = joints.size() > (has_job_level ? 1u : 0u);
  // The checkpoint dimension: from the row, one column per checkpoint, or none.
  std::vector<std::optional<std::int64_t>> checkpoint_columns{std::nullopt};
  const bool checkpointed = checkpoints != nullptr;
  if (checkpointed && !checkpoint_rows) checkpoint_columns = decltype(checkpoint_columns)(checkpoints->begin(), checkpoints->end());
  for (const std::optional<std::int64_t>& checkpoint : checkpoint_columns) {
    TableColumn column;
    column.metric = MetricId{name, std::nullopt, checkpoint};
    column.checkpoint_from_row = checkpoint_rows && checkpointed;
    column.unchecked_on_checkpoint_rows = checkpoint_rows && !checkpointed;
    if (joint_rows) {
      column.joint_from_row = has_joints;
      column.job_level_on_joint_rows = !has_joints;
      column.header = make_metric_label(column.metric);
      table.columns.push_back(column);
    } else if (has_job_level) {
      column.header = make_metric_label(column.metric);
      table.columns.push_back(column);
    } else {
      for (const std::optional<int>& joint : joints) {
        if (joint && is_joint_wanted(spec, *joint)) {
          column.metric.joint = joint;
          column.header = make_metric_label(column.metric);
          table.columns.push_back(column);
        }
      }
    }
  }
}

/// The columns of every --cols metric the kept jobs have; a name the sweep lacks is refused.
void add_table_columns(const SweepData& data, const TableSpec& spec, const std::vector<const JobResult*>& jobs,
                       Table& table) {
  const MetricShapes shapes = find_metric_shapes(jobs);
  const std::vector<std::string> all_names = list_metric_names(data);
  for (const std::string& name : spec.metrics) {
    auto found = shapes.joints_by_name.find(name);
    if (found == shapes.joints_by_name.end()) {
      if (std::find(all_names.begin(), all_names.end(), name) == all_names.end()) {
        throw AnalysisError("sweep '" + data.name + "': --cols: no metric '" + name + "'" + make_suggestion(name, all_names));
      }
      continue;  // present, but not in the jobs --where kept
    }
    const auto checkpoints = shapes.checkpoints_by_name.find(name);
    add_metric_columns(spec, name, found->second,
                       checkpoints == shapes.checkpoints_by_name.end() ? nullptr : &checkpoints->second, table);
  }
}

/// Jobs grouped by their row labels (the swept parameters of --rows), in expansion order.
struct RowGroups {
  std::vector<std::vector<std::string>> labels;
  std::vector<std::vector<const JobResult*>> jobs;
};

RowGroups group_jobs_by_row(const TableSpec& spec, const std::vector<const JobResult*>& jobs) {
  RowGroups groups;
  for (const JobResult* job : jobs) {
    std::vector<std::string> labels;
    for (const std::string& row : spec.rows) {
      if (!is_dimension(row)) labels.push_back(format_param_value(find_param_value(*job, row)));
    }
    auto it = std::find(groups.labels.begin(), groups.labels.end(), labels);
    if (it == groups.labels.end()) {
      groups.labels.push_back(labels);
      groups.jobs.push_back({job});
    } else {
      groups.jobs[static_cast<std::size_t>(it - groups.labels.begin())].push_back(job);
    }
  }
  return groups;
}

/// A row aggregates repeats: its jobs may differ in their seed only.
void check_rows_pool_seeds_only(const SweepData& data, const TableSpec& spec, const RowGroups& groups) {
  for (std::size_t g = 0; g < groups.jobs.size(); ++g) {
    std::vector<std::string> differing;
    for (const std::string& path : data.varying_params) {
      if (path == "seed" || has_row(spec, path)) continue;
      const nlohmann::json first = find_param_value(*groups.jobs[g].front(), path);
      for (const JobResult* job : groups.jobs[g]) {
        if (find_param_value(*job, path) != first) {
          differing.push_back(path);
          break;
        }
      }
    }
    if (!differing.empty()) {
      std::string names, row;
      for (const std::string& path : differing) names += (names.empty() ? "" : ", ") + path;
      for (const std::string& label : groups.labels[g]) row += (row.empty() ? "" : ", ") + label;
      throw AnalysisError("sweep '" + data.name + "': the row" + (row.empty() ? "" : " (" + row + ")") +
                          " would pool jobs that differ in " + names +
                          ", not only in their seed; add them to --rows or choose with --where");
    }
  }
}

/// The 1-based number of footnote `text`, added when new.
int add_footnote(Table& table, const std::string& text) {
  auto it = std::find(table.footnotes.begin(), table.footnotes.end(), text);
  if (it != table.footnotes.end()) return static_cast<int>(it - table.footnotes.begin()) + 1;
  table.footnotes.push_back(text);
  return static_cast<int>(table.footnotes.size());
}

/// One cell's values over the done jobs of a row, and why some are missing.
struct CellValues {
  std::vector<double> values;
  int present = 0, undefined = 0;
  std::string undefined_reason, partial_note;
};

CellValues collect_cell_values(const std::vector<const JobResult*>& members, const MetricId& id) {
  CellValues cell;
  for (const JobResult* job : members) {
    if (job->status != "done") continue;
    auto found = job->metrics.find(id);
    if (found == job->metrics.end()) continue;
    ++cell.present;
    auto reason = job->reasons.find(id);
    if (std::isfinite(found->second)) {
      cell.values.push_back(found->second);
      // A job-level mean that left joints out says so: footnote it.
      bool joint_undefined = false;
      if (!id.joint) {
        for (const auto& [other, value] : job->metrics) {
          if (other.name == id.name && other.checkpoint == id.checkpoint && other.joint && !std::isfinite(value)) {
            joint_undefined = true;
          }
        }
      }
      if (joint_undefined && reason != job->reasons.end() && cell.partial_note.empty()) cell.partial_note = reason->second;
    } else {
      ++cell.undefined;
      if (cell.undefined_reason.empty()) cell.undefined_reason = reason != job->reasons.end() ? reason->second : "undefined";
    }
  }
  return cell;
}

/// The footnote of a cell (0: none): a column not shown on such rows, undefined or partial values.
int choose_cell_footnote(Table& table, const TableColumn& column, const MetricId& id, const CellValues& cell) {
  const std::string where = column.metric.name + (id.joint ? ", joint " + std::to_string(*id.joint) : std::string()) +
                            (id.checkpoint ? ", checkpoint " + std::to_string(*id.checkpoint) : std::string());
  if (column.job_level_on_joint_rows) return add_footnote(table, column.metric.name + ": a job-level metric, no per-joint value");
  if (column.unchecked_on_checkpoint_rows) {
    return add_footnote(table, column.metric.name + ": a training-run metric, not evaluated per checkpoint");
  }
  if (cell.undefined > 0) {
    return add_footnote(table, where + ": undefined in " + std::to_string(cell.undefined) + " of " +
                                   std::to_string(cell.present) + " jobs: " + cell.undefined_reason);
  }
  if (!cell.partial_note.empty()) return add_footnote(table, where + ": " + cell.partial_note);
  return 0;
}

/// One row: the group's labels (and its joint and checkpoint), its job counts and a cell per column.
TableRow make_row(const TableSpec& spec, const std::vector<std::string>& labels, const std::vector<const JobResult*>& members,
                  std::optional<int> joint, std::optional<std::int64_t> checkpoint, Table& table) {
  TableRow row;
  row.joint = joint;
  row.checkpoint = checkpoint;
  std::size_t label_index = 0;
  for (const std::string& header : spec.rows) {
    if (header == "joint") row.labels.push_back(std::to_string(joint.value_or(0)));
    else if (header == "checkpoint") row.labels.push_back(std::to_string(checkpoint.value_or(0)));
    else row.labels.push_back(labels[label_index++]);
  }
  for (const JobResult* job : members) {
    if (job->status == "done") ++row.jobs_done;
    else if (is_finished_badly(job->status)) ++row.jobs_failed;
    else ++row.jobs_unfinished;
  }
  for (const TableColumn& column : table.columns) {
    MetricId id = column.metric;
    if (column.joint_from_row) id.joint = joint;
    if (column.checkpoint_from_row) id.checkpoint = checkpoint;
    const bool not_shown = column.job_level_on_joint_rows || column.unchecked_on_checkpoint_rows;
    CellValues cell = not_shown ? CellValues{} : collect_cell_values(members, id);
    row.cells.push_back(calc_summary_statistics(std::move(cell.values)));
    row.footnotes.push_back(choose_cell_footnote(table, column, id, cell));
  }
  return row;
}

/// Each group expands over its joints and checkpoints, nested in the order of spec.rows.
void add_table_rows(const TableSpec& spec, const RowGroups& groups, Table& table) {
  const bool joint_rows = has_row(spec, "joint");
  const bool checkpoint_rows = has_row(spec, "checkpoint");
  const auto joint_at = std::find(spec.rows.begin(), spec.rows.end(), "joint");
  const auto checkpoint_at = std::find(spec.rows.begin(), spec.rows.end(), "checkpoint");
  const bool joint_outer = joint_at < checkpoint_at;
  for (std::size_t g = 0; g < groups.labels.size(); ++g) {
    std::set<std::optional<int>> group_joints;
    std::set<std::optional<std::int64_t>> group_checkpoints;
    for (const JobResult* job : groups.jobs[g]) {
      for (const auto& [id, value] : job->metrics) {
        if (id.joint && is_joint_wanted(spec, *id.joint)) group_joints.insert(id.joint);
        if (id.checkpoint) group_checkpoints.insert(id.checkpoint);
      }
    }
    if (!joint_rows) group_joints = {std::nullopt};
    if (!checkpoint_rows) group_checkpoints = {std::nullopt};
    if (joint_outer) {
      for (const auto& joint : group_joints) {
        for (const auto& checkpoint : group_checkpoints) table.rows.push_back(make_row(spec, groups.labels[g], groups.jobs[g], joint, checkpoint, table));
      }
    } else {
      for (const auto& checkpoint : group_checkpoints) {
        for (const auto& joint : group_joints) table.rows.push_back(make_row(spec, groups.labels[g], groups.jobs[g], joint, checkpoint, table));
      }
    }
  }
}

}  // namespace

Table make_table(const SweepData& data, const TableSpec& spec) {
  Table table;
  table.title = spec.title;
  check_table_rows(data, spec);
  table.row_headers = spec.rows;
  const std::vector<const JobResult*> jobs = select_table_jobs(data, spec);
  add_table_columns(data, spec, jobs, table);
  const RowGroups groups = group_jobs_by_row(spec, jobs);
  check_rows_pool_seeds_only(data, spec, groups);
  add_table_rows(spec, groups, table);
  return table;
}

std::vector<TableSpec> make_default_table_specs(const SweepData& data) {
  std::set<std::string> names;
  for (const JobResult& job : data.jobs) {
    for (const auto& [id, value] : job.metrics) names.insert(id.name);
  }
  std::vector<std::string> swept;
  for (const std::string& path : data.varying_params) {
    if (path != "seed") swept.push_back(path);
  }
  auto present = [&](std::vector<std::string> wanted) {
    std::vector<std::string> kept;
    for (const std::string& name : wanted) {
      if (names.count(name)) kept.push_back(name);
    }
    return kept;
  };

  std::vector<TableSpec> specs;
  const auto ff_fb = present({"ff_fb_ratio_avg", "ff_fb_ratio_var", "ff_abs_avg", "fb_abs_avg"});
  if (!ff_fb.empty()) {
    std::vector<std::string> rows = swept;
    rows.push_back("joint");
    specs.push_back({"Training run: feed-forward to feedback ratio per joint (thesis tables 6.1, 6.4-6.7)", rows, ff_fb, {}, {}});
  }
  const auto tracking = present({"tracking_nmse_x", "tracking_nmse_y", "tracking_nmse_z", "tracking_nmse",
                                  "tracking_rmse_x", "tracking_rmse_y", "tracking_rmse_z", "tracking_rmse", "task_rmse"});
  if (!tracking.empty()) {
    specs.push_back({"Training run: tracking nMSE and RMSE per task axis, mean over joints (thesis tables 6.2-6.3)", swept, tracking, {}, {}});
  }
  const auto learned = present({"same_run_test_nmse", "same_run_test_rmse", "id_nmse", "id_rmse", "n_receptive_fields"});
  if (!learned.empty()) {
    specs.push_back({"Training run: learned model nMSE, RMSE and receptive fields (thesis figures 6.1-6.2)", swept, learned, {}, {}});
  }
  // Held-out evaluation (metrics heldout_*, one value per checkpoint): the frozen learner's
  // figures per checkpoint, then its control pass's ff/fb statistics per checkpoint and joint.
  std::vector<std::string> checkpoint_rows = swept;
  checkpoint_rows.push_back("checkpoint");
  const auto heldout = present({"heldout_test_nmse", "heldout_test_rmse", "heldout_tracking_nmse", "heldout_task_rmse",
                                 "heldout_id_nmse", "heldout_n_receptive_fields", "heldout_learner_updates",
                                 "heldout_diverged"});
  if (!heldout.empty()) {
    specs.push_back({"Held-out evaluation per checkpoint, frozen learner: nMSE, tracking and receptive fields",
                     checkpoint_rows, heldout, {}, {}});
  }
  const auto heldout_ff_fb = present({"heldout_ff_fb_ratio_avg", "heldout_ff_fb_ratio_var", "heldout_ff_abs_avg",
                                       "heldout_fb_abs_avg"});
  if (!heldout_ff_fb.empty()) {
    std::vector<std::string> rows = checkpoint_rows;
    rows.push_back("joint");
    specs.push_back({"Held-out evaluation per checkpoint and joint: feed-forward to feedback ratio", rows, heldout_ff_fb, {}, {}});
  }
  if (specs.empty()) {
    std::vector<std::string> job_level;
    for (const JobResult& job : data.jobs) {
      for (const auto& [id, value] : job.metrics) {
        if (!id.joint && std::find(job_level.begin(), job_level.end(), id.name) == job_level.end()) {
          job_level.push_back(id.name);
        }
      }
    }
    specs.push_back({"Metrics", swept, job_level, {}, {}});
  }
  return specs;
}

namespace {

std::string format_cell(const SummaryStatistics& cell, Aggregate aggregate, bool latex, int footnote = 0) {
  const std::string mark = footnote ? (latex ? "$^{" + std::to_string(footnote) + "}$" : " [" + std::to_string(footnote) + "]") : "";
  if (cell.count == 0) return (latex ? std::string("--") : std::string("–")) + mark;
  // The mean carries its 95 % Student-t interval over the repeats; other aggregates stand alone.
  std::string text = aggregate == Aggregate::mean ? format_mean_ci(cell) : format_table_number(cell.value(aggregate));
  if (cell.count > 1) text += " (n=" + std::to_string(cell.count) + ")";
  return text + mark;
}

std::string format_status(const TableRow& row) {
  std::string text = std::to_string(row.jobs_done);
  if (row.jobs_failed > 0) text += ", " + std::to_string(row.jobs_failed) + " failed";
  if (row.jobs_unfinished > 0) text += ", " + std::to_string(row.jobs_unfinished) + " unfinished";
  return text;
}

std::string escape_latex(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '_': out += "\\_"; break;
      case '%': out += "\\%"; break;
      case '&': out += "\\&"; break;
      case '#': out += "\\#"; break;
      case '$': out += "\\$"; break;
      case '{': out += "\\{"; break;
      case '}': out += "\\}"; break;
      default: out += c;
    }
  }
  return out;
}

// A Markdown table cell on one line: a line break as <br> (GitHub's way inside a cell) and a
// pipe escaped, so that a value holding either does not end the row or the cell.
std::string escape_markdown_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n') out += "<br>";
    else if (c == '|') out += "\\|";
    else out += c;
  }
  return out;
}

std::string escape_csv(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// Markdown: a "###" title, the table, then its footnotes "[k] …" (two spaces: a line break).
void write_markdown_table(std::ostream& out, const Table& table, Aggregate aggregate) {
  if (!table.title.empty()) out << "### " << escape_markdown_cell(table.title) << "\n\n";  // a heading is one line too
  out << "|";
  for (const std::string& header : table.row_headers) out << " " << escape_markdown_cell(header) << " |";
  for (const TableColumn& column : table.columns) out << " " << escape_markdown_cell(column.header) << " |";
  out << " jobs done |\n|";
  for (std::size_t i = 0; i < table.row_headers.size() + table.columns.size() + 1; ++i) out << "---|";
  out << "\n";
  for (const TableRow& row : table.rows) {
    out << "|";
    for (const std::string& label : row.labels) out << " " << escape_markdown_cell(label) << " |";
    for (std::size_t c = 0; c < row.cells.size(); ++c) out << " " << format_cell(row.cells[c], aggregate, false, row.footnotes[c]) << " |";
    out << " " << format_status(row) << " |\n";
  }
  out << "\n";
  for (std::size_t f = 0; f < table.footnotes.size(); ++f) out << "[" << f + 1 << "] " << table.footnotes[f] << "  \n";
  if (!table.footnotes.empty()) out << "\n";
}

// CSV: per metric its value, std, n and 95 % interval; undefined cells empty, their reasons
// after the table as "# [k] …" lines only when asked for (pandas reads them as data).
void write_csv_table(std::ostream& out, const Table& table, Aggregate aggregate, CsvNotes csv_notes) {
  bool first = true;
  auto field = [&](const std::string& text) {
    out << (first ? "" : ",") << escape_csv(text);
    first = false;
  };
  for (const std::string& header : table.row_headers) field(header);
  for (const TableColumn& column : table.columns) {
    for (const char* suffix : {"", " std", " n", " ci95_low", " ci95_high"}) field(column.header + suffix);
  }
  for (const char* count : {"jobs_done", "jobs_failed", "jobs_unfinished"}) field(count);
  out << "\n";
  for (const TableRow& row : table.rows) {
    first = true;
    for (const std::string& label : row.labels) field(label);
    for (const SummaryStatistics& cell : row.cells) {
      field(cell.count ? format_shortest_number(cell.value(aggregate)) : "");
      field(cell.count ? format_shortest_number(cell.std_dev) : "");
      field(std::to_string(cell.count));
      field(cell.has_ci() ? format_shortest_number(cell.ci_low) : "");
      field(cell.has_ci() ? format_shortest_number(cell.ci_high) : "");
    }
    field(std::to_string(row.jobs_done));
    field(std::to_string(row.jobs_failed));
    field(std::to_string(row.jobs_unfinished));
    out << "\n";
  }
  if (csv_notes == CsvNotes::comment_lines) {
    for (std::size_t f = 0; f < table.footnotes.size(); ++f) out << "# [" << f + 1 << "] " << table.footnotes[f] << "\n";
  }
}

// LaTeX: a table float, its footnotes as superscripted paragraphs, the title as its caption.
void write_latex_table(std::ostream& out, const Table& table, Aggregate aggregate) {
  const std::size_t n_columns = table.row_headers.size() + table.columns.size() + 1;
  out << "% " << table.title << "\n\\begin{table}[ht]\n\\centering\n\\begin{tabular}{" << std::string(table.row_headers.size(), 'l')
      << std::string(n_columns - table.row_headers.size(), 'r') << "}\n\\hline\n";
  std::vector<std::string> headers;
  for (const std::string& header : table.row_headers) headers.push_back(escape_latex(header));
  for (const TableColumn& column : table.columns) headers.push_back(escape_latex(column.header));
  headers.push_back("jobs");
  const auto write_row = [&out](const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? " & " : "") << cells[i];
    out << " \\\\\n";
  };
  write_row(headers);
  out << "\\hline\n";
  for (const TableRow& row : table.rows) {
    std::vector<std::string> cells;
    for (const std::string& label : row.labels) cells.push_back(escape_latex(label));
    for (std::size_t c = 0; c < row.cells.size(); ++c) cells.push_back(format_cell(row.cells[c], aggregate, true, row.footnotes[c]));
    cells.push_back(escape_latex(format_status(row)));
    write_row(cells);
  }
  out << "\\hline\n\\end{tabular}\n";
  for (std::size_t f = 0; f < table.footnotes.size(); ++f) {
    out << "\\par{\\footnotesize $^{" << f + 1 << "}$ " << escape_latex(table.footnotes[f]) << "}\n";
  }
  out << "\\caption{" << escape_latex(table.title) << "}\n\\end{table}\n";
}

// JSON: one object per cell with its n, note, aggregate value and statistics.
nlohmann::json make_json_cell(const Table& table, const TableRow& row, std::size_t c, Aggregate aggregate) {
  const SummaryStatistics& cell = row.cells[c];
  nlohmann::json value = {{"n", cell.count}};
  if (row.footnotes[c]) value["note"] = table.footnotes[static_cast<std::size_t>(row.footnotes[c] - 1)];
  if (cell.count > 0) {
    value["value"] = cell.value(aggregate);
    value["mean"] = cell.mean;
    value["std"] = cell.std_dev;
    if (cell.has_ci()) value["ci95"] = {cell.ci_low, cell.ci_high};
    value["min"] = cell.min;
    value["max"] = cell.max;
    value["median"] = cell.median;
  }
  return value;
}

void write_json_table(std::ostream& out, const Table& table, Aggregate aggregate) {
  nlohmann::json rows = nlohmann::json::array();
  for (const TableRow& row : table.rows) {
    nlohmann::json entry;
    for (std::size_t i = 0; i < row.labels.size(); ++i) entry["params"][table.row_headers[i]] = row.labels[i];
    entry["jobs_done"] = row.jobs_done;
    entry["jobs_failed"] = row.jobs_failed;
    entry["jobs_unfinished"] = row.jobs_unfinished;
    entry["cells"] = nlohmann::json::object();
    for (std::size_t c = 0; c < table.columns.size(); ++c) entry["cells"][table.columns[c].header] = make_json_cell(table, row, c, aggregate);
    rows.push_back(entry);
  }
  nlohmann::json document = {{"title", table.title}, {"aggregate", to_string(aggregate)}, {"rows", rows}, {"footnotes", table.footnotes}};
  out << document.dump(2) << "\n";
}

}  // namespace

std::string format_table(const Table& table, TableFormat format, Aggregate aggregate, CsvNotes csv_notes) {
  std::ostringstream out;
  switch (format) {
    case TableFormat::markdown: write_markdown_table(out, table, aggregate); break;
    case TableFormat::csv: write_csv_table(out, table, aggregate, csv_notes); break;
    case TableFormat::latex: write_latex_table(out, table, aggregate); break;
    case TableFormat::json: write_json_table(out, table, aggregate); break;
  }
  return out.str();
}

}  // namespace armfarm
