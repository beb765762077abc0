// `armfarm table DB [--sweep NAME]`: one row per job, its varying parameters against the main
// metrics (a joint's metric is the column name_j<joint>). The analysis commands refine this.
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <cstdio>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

namespace armfarm::cli {
namespace {

// Shown by default when present; otherwise every metric of the sweep is.
const std::vector<std::string> kMainMetrics = {"tracking_nmse", "test_nmse", "ff_fb_ratio_avg"};

std::string format_cell(const nlohmann::json& value) {
  if (value.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value.get<double>());
    return text;
  }
  return value.is_string() ? value.get<std::string>() : value.dump();
}

void print_sweep_table(const ResultsStore& store, const std::string& sweep, const std::vector<std::string>& wanted) {
  const std::vector<JobRecord> jobs = store.find_jobs(sweep);
  const std::vector<MetricRecord> metrics = store.find_sweep_metrics(sweep);
  std::set<std::string> param_names;
  for (const JobRecord& job : jobs) {
    for (const auto& item : job.params.items()) param_names.insert(item.key());
  }
  std::set<std::string> present;
  for (const MetricRecord& m : metrics) present.insert(m.name);
  std::set<std::string> shown;
  for (const std::string& name : wanted) {
    if (present.count(name)) shown.insert(name);
  }
  if (shown.empty()) shown = present;
  std::vector<std::pair<std::string, std::optional<int>>> metric_columns;
  {
    std::set<std::pair<std::string, int>> seen;
    for (const MetricRecord& m : metrics) {
      if (shown.count(m.name) && seen.insert({m.name, m.joint.value_or(0)}).second) metric_columns.emplace_back(m.name, m.joint);
    }
    std::sort(metric_columns.begin(), metric_columns.end());
  }
  std::map<std::int64_t, std::map<std::pair<std::string, int>, double>> values;
  for (const MetricRecord& m : metrics) values[m.job_id][{m.name, m.joint.value_or(0)}] = m.value;

  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"key"};
  header.insert(header.end(), param_names.begin(), param_names.end());
  header.push_back("status");
  for (const auto& [name, joint] : metric_columns) header.push_back(joint ? name + "_j" + std::to_string(*joint) : name);
  rows.push_back(header);
  for (const JobRecord& job : jobs) {
    std::vector<std::string> row = {job.key.substr(0, 8)};
    for (const std::string& param : param_names) row.push_back(job.params.contains(param) ? format_cell(job.params[param]) : "");
    row.push_back(job.status);
    for (const auto& [name, joint] : metric_columns) {
      const auto& job_values = values[job.id];
      const auto found = job_values.find({name, joint.value_or(0)});
      row.push_back(found == job_values.end() ? "" : format_cell(found->second));
    }
    rows.push_back(row);
  }
  std::vector<std::size_t> widths(header.size(), 0);
  for (const auto& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  }
  std::cout << "sweep " << sweep << " (" << jobs.size() << " jobs)\n";
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      line += row[c] + std::string(widths[c] - row[c].size() + (c + 1 < row.size() ? 2 : 0), ' ');
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    std::cout << line << "\n";
  }
}

}  // namespace

RunFunction setup_table(CLI::App& parent) {
  struct Options {
    std::string db;
    std::string sweep;
    std::vector<std::string> metrics;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("table", "Print each job's varying parameters against its main metrics");
  app->add_option("db", options->db, "Results database")->required();
  app->add_option("--sweep", options->sweep, "Only this sweep (default: all)");
  app->add_option("--metrics", options->metrics, "Metric names to show (default: tracking_nmse, test_nmse, "
                                                 "ff_fb_ratio_avg when present, otherwise all)")
      ->delimiter(',');

  return [options] {
    const ResultsStore store = ResultsStore::open(options->db, ResultsStore::Mode::read_only);
    std::vector<std::string> sweeps;
    if (!options->sweep.empty()) {
      if (!store.find_sweep(options->sweep)) {
        std::cerr << "armfarm: " << options->db << ": no sweep named '" << options->sweep << "'\n";
        return 2;
      }
      sweeps.push_back(options->sweep);
    } else {
      for (const SweepRecord& sweep : store.find_sweeps()) sweeps.push_back(sweep.name);
    }
    const std::vector<std::string> wanted = options->metrics.empty() ? kMainMetrics : options->metrics;
    for (std::size_t i = 0; i < sweeps.size(); ++i) {
      if (i > 0) std::cout << "\n";
      print_sweep_table(store, sweeps[i], wanted);
    }
    return 0;
  };
}

}  // namespace armfarm::cli
