#include "runner/io/sweep_export.hpp"

#include "base/number_format.hpp"
#include "runner/io/csv_writing.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace armfarm {

namespace {

// The swept parameters of a sweep's jobs, in first-seen order.
std::vector<std::string> find_swept_params(const std::vector<JobRecord>& jobs) {
  std::vector<std::string> params;
  for (const JobRecord& job : jobs) {
    for (const auto& [path, value] : job.params.items()) {
      if (std::find(params.begin(), params.end(), path) == params.end()) params.push_back(path);
    }
  }
  return params;
}

// ",value,value,..." of a job's swept parameters (empty where the job lacks one).
std::string make_param_fields(const JobRecord& job, const std::vector<std::string>& params) {
  std::string fields;
  for (const std::string& param : params) {
    fields += ",";
    if (job.params.contains(param)) fields += make_csv_value_field(job.params.at(param));
  }
  return fields;
}

}  // namespace

LongFormSignal make_long_form_signal(const std::string& series, const std::string& column) {
  if (column.size() >= 2 && column[0] == 'j' && column[1] != '0' &&
      std::all_of(column.begin() + 1, column.end(), [](char c) { return c >= '0' && c <= '9'; }) && column.size() <= 6) {
    return {std::stoi(column.substr(1)), series};
  }
  return {std::nullopt, series + "." + column};
}

SweepExportCounts write_sweep_long_csv(const ResultsStore& store, const std::string& sweep,
                                       const std::vector<std::string>& series, std::ostream& out) {
  const std::vector<JobRecord> jobs = store.find_jobs(sweep);
  const std::vector<std::string> params = find_swept_params(jobs);
  // Which series exist, to check the requested names before writing anything.
  std::set<std::string> recorded;
  std::vector<std::vector<std::string>> names_by_job(jobs.size());
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (jobs[i].status != "done") continue;
    names_by_job[i] = store.find_series_names(jobs[i].id);
    recorded.insert(names_by_job[i].begin(), names_by_job[i].end());
  }
  for (const std::string& name : series) {
    if (recorded.count(name) == 0) {
      std::string have;
      for (const std::string& r : recorded) have += (have.empty() ? "" : ", ") + r;
      throw std::invalid_argument("sweep " + sweep + " has no recorded series " + name + " (it has: " +
                                  (have.empty() ? "none" : have) + ")");
    }
  }

  out << "job";
  for (const std::string& param : params) out << "," << make_csv_field(param);
  out << ",time,joint,signal,value\n";
  SweepExportCounts counts;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobRecord& job = jobs[i];
    if (job.status != "done") {
      ++counts.jobs_skipped;
      continue;
    }
    ++counts.jobs;
    const std::string prefix = make_csv_field(job.key) + make_param_fields(job, params);
    for (const std::string& name : names_by_job[i]) {
      if (!series.empty() && std::find(series.begin(), series.end(), name) == series.end()) continue;
      const std::optional<SeriesRecord> record = store.find_series(job.id, name);
      if (!record) continue;
      const auto t = std::find(record->columns.begin(), record->columns.end(), "t");
      const Eigen::Index t_column = t == record->columns.end() ? -1 : static_cast<Eigen::Index>(t - record->columns.begin());
      std::vector<std::pair<Eigen::Index, std::string>> columns;  // column index, "joint,signal"
      for (std::size_t c = 0; c < record->columns.size(); ++c) {
        if (static_cast<Eigen::Index>(c) == t_column) continue;
        const LongFormSignal signal = make_long_form_signal(name, record->columns[c]);
        columns.emplace_back(static_cast<Eigen::Index>(c),
                             (signal.joint ? std::to_string(*signal.joint) : std::string()) + "," +
                                 make_csv_field(signal.signal));
      }
      for (Eigen::Index r = 0; r < record->rows.rows(); ++r) {
        const std::string time = t_column < 0 ? std::string() : format_shortest_number(record->rows(r, t_column));
        for (const auto& [c, label] : columns) {
          out << prefix << "," << time << "," << label << "," << format_shortest_number(record->rows(r, c)) << "\n";
          ++counts.rows;
        }
      }
    }
  }
  return counts;
}

std::string describe_undefined_value(const std::string& stored_reason) {
  return stored_reason.empty() ? "undefined (no reason stored)" : stored_reason;
}

MetricExportCounts write_sweep_metrics_csv(const ResultsStore& store, const std::string& sweep, std::ostream& out) {
  const std::vector<JobRecord> jobs = store.find_jobs(sweep);
  const std::vector<std::string> params = find_swept_params(jobs);
  std::map<std::string, std::string> unit_by_name;
  for (const MetricInfoRecord& info : store.find_metric_info()) unit_by_name[info.name] = info.unit;
  std::map<std::int64_t, std::vector<const MetricRecord*>> metrics_by_job;
  const std::vector<MetricRecord> metrics = store.find_sweep_metrics(sweep);
  for (const MetricRecord& metric : metrics) metrics_by_job[metric.job_id].push_back(&metric);

  out << "job,status";
  for (const std::string& param : params) out << "," << make_csv_field(param);
  out << ",name,joint,checkpoint,value,unit,reason\n";
  MetricExportCounts counts;
  for (const JobRecord& job : jobs) {
    const auto found = metrics_by_job.find(job.id);
    if (found == metrics_by_job.end()) {
      ++counts.jobs_without_metrics;
      continue;
    }
    ++counts.jobs;
    const std::string prefix = make_csv_field(job.key) + "," + make_csv_field(job.status) + make_param_fields(job, params);
    for (const MetricRecord* metric : found->second) {
      const auto unit = unit_by_name.find(metric->name);
      out << prefix << "," << make_csv_field(metric->name) << "," << (metric->joint ? std::to_string(*metric->joint) : "")
          << "," << (metric->checkpoint ? std::to_string(*metric->checkpoint) : "") << ","
          << (metric->value ? format_shortest_number(*metric->value) : "") << ","
          << make_csv_field(unit == unit_by_name.end() ? std::string() : unit->second) << ","
          << make_csv_field(metric->value ? metric->reason : describe_undefined_value(metric->reason))
          << "\n";
      ++counts.rows;
    }
  }
  return counts;
}

}  // namespace armfarm
