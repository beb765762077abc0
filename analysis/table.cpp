#include "analysis/table.hpp"

#include "analysis/analysis_error.hpp"

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
  if (value.is_number()) return format_number(value.get<double>());
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

Table make_table(const SweepData& data, const TableSpec& spec) {
  Table table;
  table.title = spec.title;
  const bool joint_rows = std::find(spec.rows.begin(), spec.rows.end(), "joint") != spec.rows.end();

  // Jobs kept by --where.
  std::vector<const JobResult*> jobs;
  for (const JobResult& job : data.jobs) {
    bool keep = true;
    for (const auto& [path, wanted] : spec.where) {
      if (!param_matches(find_param_value(job, path), wanted)) keep = false;
    }
    if (keep) jobs.push_back(&job);
  }

  for (const std::string& row : spec.rows) {
    if (row == "joint") continue;
    const bool known = std::any_of(data.jobs.begin(), data.jobs.end(),
                                   [&](const JobResult& job) { return !find_param_value(job, row).is_null(); });
    if (!known) throw AnalysisError("sweep '" + data.name + "': no parameter '" + row + "'");
  }
  table.row_headers = spec.rows;

  // Which metric ids exist: decide per metric between job-level and per-joint columns.
  std::set<int> joints_present;
  std::map<std::string, std::set<std::optional<int>>> ids_by_name;
  for (const JobResult* job : jobs) {
    for (const auto& [id, value] : job->metrics) {
      ids_by_name[id.name].insert(id.joint);
      if (id.joint) joints_present.insert(*id.joint);
    }
  }
  auto joint_wanted = [&](int joint) {
    return spec.joints.empty() || std::find(spec.joints.begin(), spec.joints.end(), joint) != spec.joints.end();
  };
  for (const std::string& name : spec.metrics) {
    auto found = ids_by_name.find(name);
    if (found == ids_by_name.end()) {
      const bool anywhere = std::any_of(data.jobs.begin(), data.jobs.end(), [&](const JobResult& job) {
        return std::any_of(job.metrics.begin(), job.metrics.end(), [&](const auto& m) { return m.first.name == name; });
      });
      if (!anywhere) throw AnalysisError("sweep '" + data.name + "': no metric '" + name + "'");
      continue;  // present, but not in the jobs --where kept
    }
    const bool per_joint = found->second.count(std::nullopt) == 0;
    if (!per_joint) {
      table.columns.push_back({name, MetricId{name, std::nullopt}, false});
    } else if (joint_rows) {
      table.columns.push_back({name, MetricId{name, std::nullopt}, true});
    } else {
      for (const std::optional<int>& joint : found->second) {
        if (joint && joint_wanted(*joint)) {
          table.columns.push_back({name + " j" + std::to_string(*joint), MetricId{name, joint}, false});
        }
      }
    }
  }

  // Group jobs by their row labels, in expansion order.
  std::vector<std::vector<std::string>> group_labels;
  std::vector<std::vector<const JobResult*>> group_jobs;
  for (const JobResult* job : jobs) {
    std::vector<std::string> labels;
    for (const std::string& row : spec.rows) {
      if (row != "joint") labels.push_back(format_param_value(find_param_value(*job, row)));
    }
    auto it = std::find(group_labels.begin(), group_labels.end(), labels);
    if (it == group_labels.end()) {
      group_labels.push_back(labels);
      group_jobs.push_back({job});
    } else {
      group_jobs[static_cast<std::size_t>(it - group_labels.begin())].push_back(job);
    }
  }

  auto make_row = [&](const std::vector<std::string>& labels, const std::vector<const JobResult*>& members,
                      std::optional<int> joint) {
    TableRow row;
    row.joint = joint;
    std::size_t label_index = 0;
    for (const std::string& header : spec.rows) {
      row.labels.push_back(header == "joint" ? std::to_string(joint.value_or(0)) : labels[label_index++]);
    }
    for (const JobResult* job : members) {
      if (job->status == "done") ++row.jobs_done;
      else if (is_finished_badly(job->status)) ++row.jobs_failed;
      else ++row.jobs_unfinished;
    }
    for (const TableColumn& column : table.columns) {
      MetricId id = column.metric;
      if (column.joint_from_row) id.joint = joint;
      std::vector<double> values;
      for (const JobResult* job : members) {
        if (job->status != "done") continue;
        auto found = job->metrics.find(id);
        if (found != job->metrics.end() && std::isfinite(found->second)) values.push_back(found->second);
      }
      row.cells.push_back(calc_summary_statistics(std::move(values)));
    }
    return row;
  };

  for (std::size_t g = 0; g < group_labels.size(); ++g) {
    if (!joint_rows) {
      table.rows.push_back(make_row(group_labels[g], group_jobs[g], std::nullopt));
      continue;
    }
    std::set<int> group_joints;
    for (const JobResult* job : group_jobs[g]) {
      for (const auto& [id, value] : job->metrics) {
        if (id.joint && joint_wanted(*id.joint)) group_joints.insert(*id.joint);
      }
    }
    for (int joint : group_joints) table.rows.push_back(make_row(group_labels[g], group_jobs[g], joint));
  }
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
    specs.push_back({"Feed-forward to feedback ratio per joint (thesis tables 6.1, 6.4-6.7)", rows, ff_fb, {}, {}});
  }
  const auto tracking = present({"tracking_nmse_x", "tracking_nmse_y", "tracking_nmse_z", "tracking_nmse"});
  if (!tracking.empty()) {
    specs.push_back({"Tracking nMSE per task axis and joint (thesis tables 6.2-6.3)", swept, tracking, {}, {}});
  }
  const auto learned = present({"same_run_test_nmse", "heldout_test_nmse", "id_nmse", "n_receptive_fields"});
  if (!learned.empty()) {
    specs.push_back({"Learned model: nMSE and receptive fields (thesis figures 6.1-6.2)", swept, learned, {}, {}});
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

std::string format_cell(const SummaryStatistics& cell, Aggregate aggregate, bool latex) {
  if (cell.count == 0) return "-";
  std::string text = format_number(cell.value(aggregate));
  if (aggregate == Aggregate::mean && cell.count > 1) {
    text += latex ? " $\\pm$ " : " ± ";
    text += format_number(cell.std_dev, 2);
  }
  if (cell.count > 1) text += " (n=" + std::to_string(cell.count) + ")";
  return text;
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

std::string escape_csv(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csv_number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

}  // namespace

std::string format_table(const Table& table, TableFormat format, Aggregate aggregate) {
  std::ostringstream out;
  switch (format) {
    case TableFormat::markdown: {
      if (!table.title.empty()) out << "### " << table.title << "\n\n";
      out << "|";
      for (const std::string& header : table.row_headers) out << " " << header << " |";
      for (const TableColumn& column : table.columns) out << " " << column.header << " |";
      out << " jobs done |\n|";
      for (std::size_t i = 0; i < table.row_headers.size() + table.columns.size() + 1; ++i) out << "---|";
      out << "\n";
      for (const TableRow& row : table.rows) {
        out << "|";
        for (const std::string& label : row.labels) out << " " << label << " |";
        for (const SummaryStatistics& cell : row.cells) out << " " << format_cell(cell, aggregate, false) << " |";
        out << " " << format_status(row) << " |\n";
      }
      out << "\n";
      break;
    }
    case TableFormat::csv: {
      bool first = true;
      auto field = [&](const std::string& text) {
        out << (first ? "" : ",") << escape_csv(text);
        first = false;
      };
      for (const std::string& header : table.row_headers) field(header);
      for (const TableColumn& column : table.columns) {
        field(column.header);
        field(column.header + " std");
        field(column.header + " n");
      }
      field("jobs_done");
      field("jobs_failed");
      field("jobs_unfinished");
      out << "\n";
      for (const TableRow& row : table.rows) {
        first = true;
        for (const std::string& label : row.labels) field(label);
        for (const SummaryStatistics& cell : row.cells) {
          field(cell.count ? csv_number(cell.value(aggregate)) : "");
          field(cell.count ? csv_number(cell.std_dev) : "");
          field(std::to_string(cell.count));
        }
        field(std::to_string(row.jobs_done));
        field(std::to_string(row.jobs_failed));
        field(std::to_string(row.jobs_unfinished));
        out << "\n";
      }
      break;
    }
    case TableFormat::latex: {
      const std::size_t n_columns = table.row_headers.size() + table.columns.size() + 1;
      out << "% " << table.title << "\n\\begin{table}[ht]\n\\centering\n\\begin{tabular}{"
          << std::string(table.row_headers.size(), 'l') << std::string(n_columns - table.row_headers.size(), 'r')
          << "}\n\\hline\n";
      bool first = true;
      for (const std::string& header : table.row_headers) {
        out << (first ? "" : " & ") << escape_latex(header);
        first = false;
      }
      for (const TableColumn& column : table.columns) {
        out << (first ? "" : " & ") << escape_latex(column.header);
        first = false;
      }
      out << (first ? "" : " & ") << "jobs \\\\\n\\hline\n";
      for (const TableRow& row : table.rows) {
        first = true;
        for (const std::string& label : row.labels) {
          out << (first ? "" : " & ") << escape_latex(label);
          first = false;
        }
        for (const SummaryStatistics& cell : row.cells) {
          out << (first ? "" : " & ") << format_cell(cell, aggregate, true);
          first = false;
        }
        out << (first ? "" : " & ") << escape_latex(format_status(row)) << " \\\\\n";
      }
      out << "\\hline\n\\end{tabular}\n\\caption{" << escape_latex(table.title) << "}\n\\end{table}\n";
      break;
    }
    case TableFormat::json: {
      nlohmann::json rows = nlohmann::json::array();
      for (const TableRow& row : table.rows) {
        nlohmann::json entry;
        for (std::size_t i = 0; i < row.labels.size(); ++i) entry["params"][table.row_headers[i]] = row.labels[i];
        entry["jobs_done"] = row.jobs_done;
        entry["jobs_failed"] = row.jobs_failed;
        entry["jobs_unfinished"] = row.jobs_unfinished;
        entry["cells"] = nlohmann::json::object();
        for (std::size_t c = 0; c < table.columns.size(); ++c) {
          const SummaryStatistics& cell = row.cells[c];
          nlohmann::json value = {{"n", cell.count}};
          if (cell.count > 0) {
            value["value"] = cell.value(aggregate);
            value["mean"] = cell.mean;
            value["std"] = cell.std_dev;
            value["min"] = cell.min;
            value["max"] = cell.max;
            value["median"] = cell.median;
          }
          entry["cells"][table.columns[c].header] = value;
        }
        rows.push_back(entry);
      }
      nlohmann::json document = {{"title", table.title}, {"aggregate", to_string(aggregate)}, {"rows", rows}};
      out << document.dump(2) << "\n";
      break;
    }
  }
  return out.str();
}

}  // namespace armfarm
