#include "analysis/sweep_data.hpp"

#include "analysis/analysis_error.hpp"
#include "base/config_path.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace armfarm {

bool MetricId::operator<(const MetricId& other) const {
  // Job-level metrics (no joint) sort before the joints of the same name.
  return std::make_tuple(name, joint.has_value(), joint.value_or(0), checkpoint.has_value(), checkpoint.value_or(0)) <
         std::make_tuple(other.name, other.joint.has_value(), other.joint.value_or(0), other.checkpoint.has_value(),
                         other.checkpoint.value_or(0));
}

bool MetricId::operator==(const MetricId& other) const {
  return name == other.name && joint == other.joint && checkpoint == other.checkpoint;
}

std::string make_metric_label(const MetricId& id) {
  return make_metric_column_name(id.name, id.joint, id.checkpoint);
}

MetricInfoTable load_metric_info(const ResultsStore& store) {
  MetricInfoTable table;
  for (MetricInfoRecord& record : store.find_metric_info()) table[record.name] = std::move(record);
  return table;
}

std::string make_readable_metric_name(const std::string& name) {
  static const std::map<std::string, std::string> kWords = {
      {"nmse", "nMSE"}, {"rmse", "RMSE"}, {"ff", "feed-forward"}, {"fb", "feedback"}, {"id", "ID"}, {"rf", "RF"},
      {"avg", "mean"},  {"abs", "absolute"},   {"us", "µs"},           {"heldout", "held-out"}, {"pd", "PD"}};
  std::string readable, word;
  std::size_t index = 0;
  auto flush = [&] {
    std::string shown = word;
    if (index == 0 && word == "n") shown = "";  // "n_receptive_fields": the unit says "count"
    else if (const auto found = kWords.find(word); found != kWords.end()) shown = found->second;
    if (!shown.empty()) readable += (readable.empty() ? "" : " ") + shown;
    word.clear();
    ++index;
  };
  for (char c : name) {
    if (c == '_') flush();
    else word += c;
  }
  flush();
  // "same run" reads as one modifier.
  const auto same_run = readable.find("same run ");
  if (same_run != std::string::npos) readable.replace(same_run, 9, "same-run ");
  return readable;
}

std::string make_readable_metric_label(const MetricId& id) {
  std::string label = make_readable_metric_name(id.name);
  if (id.joint) label += ", joint " + std::to_string(*id.joint);
  if (id.checkpoint) label += ", checkpoint " + std::to_string(*id.checkpoint);
  return label;
}

std::string make_metric_axis_label(const MetricInfoTable& info, const MetricId& id) {
  const std::string label = make_readable_metric_label(id);
  const auto found = info.find(id.name);
  if (found == info.end()) return label;
  const std::string& unit = found->second.unit;
  return unit.empty() || unit == "1" ? label : label + " (" + unit + ")";
}

const nlohmann::json* find_config_value(const nlohmann::json& config, const std::string& text) {
  ConfigPath path;
  try {
    path = parse_config_path(text);
  } catch (const std::invalid_argument&) {
    return nullptr;
  }
  const nlohmann::json* node = &config;
  for (const PathSegment& segment : path) {
    if (segment.index) {
      if (!node->is_array() || *segment.index >= node->size()) return nullptr;
      node = &(*node)[*segment.index];
    } else {
      if (!node->is_object()) return nullptr;
      const auto found = node->find(segment.key);
      if (found == node->end()) return nullptr;
      node = &*found;
    }
  }
  return node;
}

namespace {

// list_config_leaf_paths below `prefix`, into `paths`.
void add_config_leaf_paths(const nlohmann::json& node, const ConfigPath& prefix, std::vector<ConfigPath>& paths) {
  if (node.is_object()) {
    for (const auto& item : node.items()) add_config_leaf_paths(item.value(), prefix.child(item.key()), paths);
  } else if (!prefix.empty()) {
    paths.push_back(prefix);
  }
}

}  // namespace

std::vector<ConfigPath> list_config_leaf_paths(const nlohmann::json& config) {
  std::vector<ConfigPath> paths;
  add_config_leaf_paths(config, ConfigPath(), paths);
  return paths;
}

nlohmann::json find_param_value(const JobResult& job, const std::string& path) {
  if (job.params.is_object()) {
    auto it = job.params.find(path);
    if (it != job.params.end()) return *it;
  }
  if (!job.config.is_object()) return nullptr;
  const nlohmann::json* value = find_config_value(job.config, path);
  return value != nullptr ? *value : nullptr;
}

std::string choose_sweep(const ResultsStore& store, const std::optional<std::string>& requested) {
  const std::vector<SweepRecord> sweeps = store.find_sweeps();
  std::string names;
  for (const SweepRecord& sweep : sweeps) names += (names.empty() ? "" : ", ") + sweep.name;
  if (requested) {
    for (const SweepRecord& sweep : sweeps) {
      if (sweep.name == *requested) return sweep.name;
    }
    throw AnalysisError(store.path() + ": no sweep named '" + *requested + "' (sweeps: " +
                        (names.empty() ? "none" : names) + ")");
  }
  if (sweeps.size() == 1) return sweeps.front().name;
  if (sweeps.empty()) throw AnalysisError(store.path() + ": the database holds no sweep");
  throw AnalysisError(store.path() + ": several sweeps (" + names + "); choose one with --sweep");
}

std::vector<std::string> calc_varying_params(const std::vector<JobResult>& jobs) {
  std::vector<std::string> paths;
  for (const JobResult& job : jobs) {
    if (!job.params.is_object()) continue;
    for (const auto& item : job.params.items()) {
      if (std::find(paths.begin(), paths.end(), item.key()) == paths.end()) paths.push_back(item.key());
    }
  }
  return paths;
}

SweepData load_sweep_data(const ResultsStore& store, const std::string& sweep) {
  SweepData data;
  data.name = sweep;
  std::map<std::int64_t, std::size_t> index_by_id;
  for (const JobRecord& record : store.find_jobs(sweep)) {
    JobResult job;
    job.id = record.id;
    job.key = record.key;
    job.status = record.status;
    job.message = record.message;
    job.seed = record.seed;
    job.params = record.params;
    job.config = record.config;
    index_by_id[record.id] = data.jobs.size();
    data.jobs.push_back(std::move(job));
  }
  for (const MetricRecord& metric : store.find_sweep_metrics(sweep)) {
    auto it = index_by_id.find(metric.job_id);
    if (it == index_by_id.end()) continue;
    const MetricId id{metric.name, metric.joint, metric.checkpoint};
    data.jobs[it->second].metrics[id] = metric.value.value_or(std::nan(""));
    if (!metric.reason.empty()) data.jobs[it->second].reasons[id] = metric.reason;
  }
  data.metric_info = load_metric_info(store);
  data.varying_params = calc_varying_params(data.jobs);
  return data;
}

}  // namespace armfarm
