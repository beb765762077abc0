#include "analysis/comparison.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/summary_statistics.hpp"

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
  return std::any_of(metrics.begin(), metrics.end(), [](const MetricComparison& m) { return m.verdict == Verdict::regressed; });
}

namespace {

Verdict judge(double base, double next, const Tolerance& tolerance, BetterDirection direction) {
  if (std::isnan(base) && std::isnan(next)) return Verdict::within;
  const bool judged = direction == BetterDirection::lower || direction == BetterDirection::higher;
  if (std::isnan(base) != std::isnan(next)) {
    if (!judged) return Verdict::changed;
    return std::isnan(next) ? Verdict::regressed : Verdict::improved;  // a result became (un)defined
  }
  if (std::fabs(next - base) <= tolerance.atol + tolerance.rtol * std::fabs(base)) return Verdict::within;
  switch (direction) {
    case BetterDirection::lower: return next < base ? Verdict::improved : Verdict::regressed;
    case BetterDirection::higher: return next > base ? Verdict::improved : Verdict::regressed;
    case BetterDirection::none:
    case BetterDirection::unknown: return Verdict::changed;
  }
  return Verdict::changed;
}

}  // namespace

ComparisonReport compare_results(const std::vector<JobResult>& base, const std::vector<JobResult>& next,
                                 const ToleranceTable& tolerances, const std::vector<std::string>& metric_filter,
                                 const MetricInfoTable& info, bool include_timing) {
  ComparisonReport report;
  auto wanted = [&](const std::string& name) {
    return metric_filter.empty() || std::find(metric_filter.begin(), metric_filter.end(), name) != metric_filter.end();
  };
  std::map<std::string, const JobResult*> next_by_key;
  for (const JobResult& job : next) next_by_key[job.key] = &job;
  std::map<std::string, bool> base_keys;
  for (const JobResult& job : base) base_keys[job.key] = true;
  for (const JobResult& job : next) {
    if (!base_keys.count(job.key)) report.only_in_next.push_back(job.key);
  }

  for (const JobResult& base_job : base) {
    auto found = next_by_key.find(base_job.key);
    if (found == next_by_key.end()) {
      report.only_in_base.push_back(base_job.key);
      continue;
    }
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
      if (!is_result && comparison.verdict != Verdict::within) comparison.verdict = Verdict::changed;
      report.metrics.push_back(comparison);
    }
  }
  return report;
}

namespace {

const char* verdict_word(Verdict verdict) {
  switch (verdict) {
    case Verdict::within: return "ok";
    case Verdict::improved: return "improved";
    case Verdict::regressed: return "REGRESSED";
    case Verdict::changed: return "changed";
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
    regressed += m.verdict == Verdict::regressed;
    improved += m.verdict == Verdict::improved;
    changed += m.verdict == Verdict::changed;
  }
  out << "Compared " << report.jobs_paired << " jobs, " << report.metrics.size() << " metrics: " << regressed
      << " regressed, " << improved << " improved, " << changed << " changed without a better direction, "
      << (report.metrics.size() - regressed - improved - changed) << " within tolerance.\n\n";
  const bool any_outside = regressed + improved + changed > 0;
  if (any_outside || show_all) {
    out << "| job | metric | base | new | change | better | verdict |\n|---|---|---|---|---|---|---|\n";
    for (const MetricComparison& m : report.metrics) {
      if (!show_all && m.verdict == Verdict::within) continue;
      out << "| " << m.key.substr(0, 12) << " | " << make_metric_label(m.metric) << " | " << format_number(m.base, 6)
          << " | " << format_number(m.next, 6) << " | " << format_percent(m.relative_change) << " | "
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
