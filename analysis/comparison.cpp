#include "analysis/comparison.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/summary_statistics.hpp"
#include "analysis/table.hpp"
#include "base/config_path.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace armfarm {

Tolerance ToleranceTable::find(const MetricId& metric) const {
  if (metric.joint) {
    auto it = by_metric_joint.find({metric.name, *metric.joint});
    if (it != by_metric_joint.end()) return it->second;
  }
  auto it = by_metric.find(metric.name);
  return it != by_metric.end() ? it->second : defaults;
}

namespace {

Tolerance parse_tolerance_entry(const nlohmann::json& entry, const Tolerance& inherited, const std::string& source,
                                const std::string& path) {
  if (!entry.is_object()) throw AnalysisError(source + ": " + path + ": expected an object");
  Tolerance tolerance = inherited;
  for (const auto& item : entry.items()) {
    const std::string where = path + "." + item.key();
    if (item.key() == "rtol" || item.key() == "atol") {
      if (!item.value().is_number() || item.value().get<double>() < 0.0) {
        throw AnalysisError(source + ": " + where + ": expected a non-negative number");
      }
      (item.key() == "rtol" ? tolerance.rtol : tolerance.atol) = item.value().get<double>();
    } else if (item.key() == "direction") {
      if (!item.value().is_string()) throw AnalysisError(source + ": " + where + ": expected a string");
      try {
        tolerance.direction = parse_better_direction(item.value().get<std::string>());
      } catch (const std::invalid_argument& e) {
        throw AnalysisError(source + ": " + where + ": " + e.what());
      }
    } else if (item.key() != "joints") {
      throw AnalysisError(source + ": " + where + ": unknown key (expected rtol, atol, direction, joints)");
    }
  }
  return tolerance;
}

}  // namespace

ToleranceTable parse_tolerances(const std::string& text, const std::string& source, const Tolerance& defaults) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw AnalysisError(source + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  }
  if (!document.is_object()) throw AnalysisError(source + ": expected a JSON object");
  ToleranceTable table;
  table.defaults = defaults;
  for (const auto& item : document.items()) {
    if (item.key() != "default" && item.key() != "metrics") {
      throw AnalysisError(source + ": " + item.key() + ": unknown key (expected default, metrics)");
    }
  }
  if (document.contains("default")) table.defaults = parse_tolerance_entry(document["default"], defaults, source, "default");
  if (document.contains("metrics")) {
    const nlohmann::json& metrics = document["metrics"];
    if (!metrics.is_object()) throw AnalysisError(source + ": metrics: expected an object");
    for (const auto& metric : metrics.items()) {
      const std::string path = "metrics." + metric.key();
      const Tolerance tolerance = parse_tolerance_entry(metric.value(), table.defaults, source, path);
      table.by_metric[metric.key()] = tolerance;
      if (!metric.value().contains("joints")) continue;
      const nlohmann::json& joints = metric.value()["joints"];
      if (!joints.is_object()) throw AnalysisError(source + ": " + path + ".joints: expected an object");
      for (const auto& joint : joints.items()) {
        int number = 0;
        try {
          std::size_t used = 0;
          number = std::stoi(joint.key(), &used);
          if (used != joint.key().size() || number < 1) throw std::invalid_argument("joint");
        } catch (const std::exception&) {
          throw AnalysisError(source + ": " + path + ".joints." + joint.key() + ": a joint is a number from 1");
        }
        table.by_metric_joint[{metric.key(), number}] =
            parse_tolerance_entry(joint.value(), tolerance, source, path + ".joints." + joint.key());
      }
    }
  }
  return table;
}

bool ComparisonReport::regressed() const {
  if (!only_in_base.empty() || !missing_metrics.empty()) return true;
  for (const StatusChange& change : status_changes) {
    if (change.base_status == "done") return true;
  }
  return std::any_of(metrics.begin(), metrics.end(), [](const MetricComparison& m) { return m.verdict == ChangeVerdict::regressed; });
}

namespace {

ChangeVerdict judge(double base, double next, const Tolerance& tolerance, BetterDirection direction) {
  if (std::isnan(base) && std::isnan(next)) return ChangeVerdict::within;
  const bool judged = direction == BetterDirection::lower || direction == BetterDirection::higher;
  if (std::isnan(base) != std::isnan(next)) {
    if (!judged) return ChangeVerdict::changed;
    return std::isnan(next) ? ChangeVerdict::regressed : ChangeVerdict::improved;  // a result became (un)defined
  }
  if (std::fabs(next - base) <= tolerance.atol + tolerance.rtol * std::fabs(base)) return ChangeVerdict::within;
  switch (direction) {
    case BetterDirection::lower: return next < base ? ChangeVerdict::improved : ChangeVerdict::regressed;
    case BetterDirection::higher: return next > base ? ChangeVerdict::improved : ChangeVerdict::regressed;
    case BetterDirection::none:
    case BetterDirection::unknown: return ChangeVerdict::changed;
  }
  return ChangeVerdict::changed;
}

}  // namespace

namespace {

// The configuration without its recording section, as canonical text (nlohmann dumps object
// keys sorted).
std::string make_computed_config_text(const JobResult& job) {
  nlohmann::json config = job.config;
  if (config.is_object()) config.erase(kRecordingSection);
  return config.dump();
}

// Whether `path` lies in the recording section, which changes only what a job records.
bool is_recording_path(const ConfigPath& path) { return path.is_within(ConfigPath().child(kRecordingSection)); }

// The leaf paths of the configurations of `jobs` as text, sorted, each once; those of the
// recording section only `with_recording`.
std::vector<std::string> list_config_params(const std::vector<const JobResult*>& jobs, bool with_recording) {
  std::vector<std::string> texts;
  for (const JobResult* job : jobs) {
    for (const ConfigPath& path : list_config_leaf_paths(job->config)) {
      if (with_recording || !is_recording_path(path)) texts.push_back(path.to_string());
    }
  }
  std::sort(texts.begin(), texts.end());
  texts.erase(std::unique(texts.begin(), texts.end()), texts.end());
  return texts;
}

// The pairing key of a job under `pairing`.
std::string make_pairing_key(const JobResult& job, const PairingRule& pairing) {
  if (pairing.params.empty()) {
    // A job without a stored configuration pairs by its key.
    if (!job.config.is_object() || job.config.empty()) return "key " + job.key;
    return "config " + make_computed_config_text(job);
  }
  nlohmann::json values = nlohmann::json::array();
  for (const std::string& param : pairing.params) values.push_back(find_param_value(job, param));
  return values.dump();
}

// The parameters (outside recording and the pairing ones) whose values differ between a and b.
std::vector<std::string> find_differing_params(const JobResult& a, const JobResult& b, const PairingRule& pairing) {
  std::vector<std::string> differing;
  for (const std::string& path : list_config_params({&a, &b}, false)) {
    if (std::find(pairing.params.begin(), pairing.params.end(), path) != pairing.params.end()) continue;
    if (find_param_value(a, path) != find_param_value(b, path)) differing.push_back(path);
  }
  return differing;
}

// Jobs of one side by pairing key, in their order; throws AnalysisError for an ambiguous key.
std::map<std::string, const JobResult*> index_jobs(const std::vector<JobResult>& jobs, const PairingRule& pairing,
                                                   const std::string& side) {
  std::map<std::string, const JobResult*> by_key;
  for (const JobResult& job : jobs) {
    const std::string key = make_pairing_key(job, pairing);
    const auto [it, inserted] = by_key.emplace(key, &job);
    if (inserted || pairing.params.empty()) continue;
    std::string values, differing;
    for (std::size_t i = 0; i < pairing.params.size(); ++i) {
      values += (i ? ", " : "") + pairing.params[i] + "=" + find_param_value(job, pairing.params[i]).dump();
    }
    for (const std::string& path : find_differing_params(*it->second, job, pairing)) {
      differing += (differing.empty() ? "" : ", ") + path;
    }
    throw AnalysisError("--pair-by: " + side + " jobs " + it->second->key.substr(0, 8) + " and " + job.key.substr(0, 8) +
                        " both have " + values + "; add what tells them apart to --pair-by (" +
                        (differing.empty() ? "they differ in no parameter" : "they differ in " + differing) + ")");
  }
  return by_key;
}

// Checks the pairing parameters against the jobs; throws AnalysisError naming a bad one.
void check_pairing_params(const PairingRule& pairing, const std::vector<JobResult>& base,
                          const std::vector<JobResult>& next) {
  std::vector<const JobResult*> base_jobs;
  for (const JobResult& job : base) base_jobs.push_back(&job);
  const std::vector<std::string> known = list_config_params(base_jobs, true);
  for (const std::string& param : pairing.params) {
    ConfigPath path;
    try {
      path = parse_config_path(param);
    } catch (const std::invalid_argument& e) {
      throw AnalysisError("--pair-by " + param + ": not a configuration path (" + e.what() + ")");
    }
    if (is_recording_path(path)) {
      throw AnalysisError("--pair-by " + param + ": recording keys only change what is recorded and never pair jobs");
    }
    const auto has = [&](const std::vector<JobResult>& jobs) {
      return std::any_of(jobs.begin(), jobs.end(), [&](const JobResult& job) { return !find_param_value(job, param).is_null(); });
    };
    if (!has(base) && !has(next)) {
      throw AnalysisError("--pair-by " + param + ": no job has this parameter" + make_did_you_mean(param, known, make_param_name_match(param)));
    }
  }
}

}  // namespace

ComparisonReport compare_results(const std::vector<JobResult>& base, const std::vector<JobResult>& next,
                                 const ToleranceTable& tolerances, const std::vector<std::string>& metric_filter,
                                 const MetricInfoTable& info, bool include_timing, const PairingRule& pairing) {
  ComparisonReport report;
  report.pair_by = pairing.params;
  check_pairing_params(pairing, base, next);
  auto wanted = [&](const std::string& name) {
    return metric_filter.empty() || std::find(metric_filter.begin(), metric_filter.end(), name) != metric_filter.end();
  };
  const std::map<std::string, const JobResult*> next_by_key = index_jobs(next, pairing, "new");
  const std::map<std::string, const JobResult*> base_by_key = index_jobs(base, pairing, "base");
  for (const JobResult& job : next) {
    const auto found = base_by_key.find(make_pairing_key(job, pairing));
    if (found == base_by_key.end()) {
      report.only_in_next.push_back(job.key);
    }
  }

  std::map<std::string, bool> paired;
  for (const JobResult& base_job : base) {
    const std::string pairing_key = make_pairing_key(base_job, pairing);
    auto found = next_by_key.find(pairing_key);
    if (found == next_by_key.end()) {
      report.only_in_base.push_back(base_job.key);
      continue;
    }
    if (!paired.emplace(pairing_key, true).second) continue;  // a duplicate of a computed configuration
    const JobResult& next_job = *found->second;
    ++report.jobs_paired;
    if (base_job.status != next_job.status) {
      report.status_changes.push_back({base_job.key, base_job.status, next_job.status});
    }
    if (base_job.status != "done" || next_job.status != "done") continue;
    for (const auto& [id, base_value] : base_job.metrics) {
      if (!wanted(id.name)) continue;
      const bool is_result = is_result_metric(info, id.name);
      if (!is_result && !include_timing) continue;
      const Tolerance tolerance = tolerances.find(id);
      const BetterDirection direction = tolerance.direction.value_or(find_metric_direction(info, id.name));
      auto next_metric = next_job.metrics.find(id);
      if (next_metric == next_job.metrics.end()) {
        report.missing_metrics.push_back(base_job.key + ": " + make_metric_label(id));
        continue;
      }
      MetricComparison comparison;
      comparison.key = base_job.key;
      comparison.next_key = next_job.key;
      comparison.metric = id;
      comparison.base = base_value;
      comparison.next = next_metric->second;
      comparison.direction = direction;
      comparison.is_result = is_result;
      const double difference = comparison.next - comparison.base;
      comparison.relative_change = base_value != 0.0 ? difference / std::fabs(base_value)
                                   : difference == 0.0 ? 0.0
                                                       : std::copysign(std::numeric_limits<double>::infinity(), difference);
      comparison.verdict = judge(comparison.base, comparison.next, tolerance, direction);
      // Timings vary with the machine: shown when asked, never a regression.
      if (!is_result && comparison.verdict != ChangeVerdict::within) comparison.verdict = ChangeVerdict::changed;
      report.metrics.push_back(comparison);
    }
  }
  return report;
}

namespace {

const char* verdict_word(ChangeVerdict verdict) {
  switch (verdict) {
    case ChangeVerdict::within: return "ok";
    case ChangeVerdict::improved: return "improved";
    case ChangeVerdict::regressed: return "REGRESSED";
    case ChangeVerdict::changed: return "changed";
  }
  return "ok";
}

std::string format_percent(double relative) {
  if (std::isinf(relative)) return relative > 0 ? "+inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%+.3g%%", 100.0 * relative);
  return buffer;
}

}  // namespace

std::string format_comparison(const ComparisonReport& report, bool json, bool show_all) {
  if (json) {
    nlohmann::json document;
    document["regressed"] = report.regressed();
    document["jobs_paired"] = report.jobs_paired;
    document["pair_by"] = report.pair_by;
    document["only_in_base"] = report.only_in_base;
    document["only_in_new"] = report.only_in_next;
    document["missing_metrics"] = report.missing_metrics;
    document["status_changes"] = nlohmann::json::array();
    for (const StatusChange& change : report.status_changes) {
      document["status_changes"].push_back({{"key", change.key}, {"base", change.base_status}, {"new", change.next_status}});
    }
    document["metrics"] = nlohmann::json::array();
    for (const MetricComparison& m : report.metrics) {
      nlohmann::json entry = {{"key", m.key},
                              {"new_key", m.next_key},
                              {"metric", m.metric.name},
                              {"joint", m.metric.joint ? nlohmann::json(*m.metric.joint) : nlohmann::json()},
                              {"base", m.base},
                              {"new", m.next},
                              {"direction", to_string(m.direction)},
                              {"result", m.is_result},
                              {"verdict", verdict_word(m.verdict)}};
      entry["relative_change"] = std::isfinite(m.relative_change) ? nlohmann::json(m.relative_change) : nlohmann::json();
      document["metrics"].push_back(entry);
    }
    return document.dump(2) + "\n";
  }

  std::ostringstream out;
  int regressed = 0;
  int improved = 0;
  int changed = 0;
  for (const MetricComparison& m : report.metrics) {
    regressed += m.verdict == ChangeVerdict::regressed;
    improved += m.verdict == ChangeVerdict::improved;
    changed += m.verdict == ChangeVerdict::changed;
  }
  out << "Compared " << report.jobs_paired << " jobs";
  if (!report.pair_by.empty()) {
    out << " paired by";
    for (const std::string& param : report.pair_by) out << " " << param;
  }
  out << ", " << report.metrics.size() << " metrics: " << regressed
      << " regressed, " << improved << " improved, " << changed << " changed without a better direction, "
      << (report.metrics.size() - regressed - improved - changed) << " within tolerance.\n\n";
  const bool any_outside = regressed + improved + changed > 0;
  if (any_outside || show_all) {
    out << "| job | metric | base | new | change | better | verdict |\n|---|---|---|---|---|---|---|\n";
    for (const MetricComparison& m : report.metrics) {
      if (!show_all && m.verdict == ChangeVerdict::within) continue;
      out << "| " << m.key.substr(0, 12) << " | " << make_metric_label(m.metric) << " | " << format_table_number(m.base, 6)
          << " | " << format_table_number(m.next, 6) << " | " << format_percent(m.relative_change) << " | "
          << (m.is_result ? std::string(to_string(m.direction)) : std::string(to_string(m.direction)) + " (timing)")
          << " | " << verdict_word(m.verdict) << " |\n";
    }
    out << "\n";
  }
  for (const StatusChange& change : report.status_changes) {
    out << "status changed: " << change.key << " " << change.base_status << " -> " << change.next_status << "\n";
  }
  for (const std::string& key : report.only_in_base) out << "only in base: " << key << "\n";
  for (const std::string& key : report.only_in_next) out << "only in new: " << key << "\n";
  for (const std::string& missing : report.missing_metrics) out << "metric missing in new: " << missing << "\n";
  out << (report.regressed() ? "RESULT: regression\n" : "RESULT: ok\n");
  return out.str();
}

}  // namespace armfarm
