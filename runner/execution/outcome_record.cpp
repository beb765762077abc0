#include "runner/execution/outcome_record.hpp"

#include "engine/experiment/metric_catalog.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "runner/spec/canonical_json.hpp"

namespace armfarm {

std::string make_stored_model_hash(const std::string& bytes) { return "xxh3-128:" + calc_text_hash(bytes); }

JobResultRecord make_job_result_record(const std::string& key, JobOutcome outcome, double wall_seconds,
                                       const std::string& started_at, const std::string& finished_at) {
  JobResultRecord record;
  record.key = key;
  record.status = to_string(outcome.status);
  record.message = std::move(outcome.message);
  record.end_time = outcome.end_time;
  record.wall_seconds = wall_seconds;
  record.started_at = started_at;
  record.finished_at = finished_at;
  for (Metric& metric : outcome.metrics) {
    std::optional<std::int64_t> checkpoint;
    if (metric.checkpoint) checkpoint = metric.checkpoint->number;
    record.metrics.push_back({0, std::move(metric.name), metric.joint, metric.value, std::move(metric.reason), checkpoint});
  }
  for (Series& series : outcome.series) {
    record.series.push_back({0, std::move(series.name), std::move(series.columns), std::move(series.rows)});
  }
  if (!outcome.model_file.empty()) {
    StoredModelRecord model;
    model.kind = find_learner_model_kind(outcome.model_file);
    model.hash = make_stored_model_hash(outcome.model_file);
    model.data = std::move(outcome.model_file);
    record.model = std::move(model);
  }
  return record;
}

}  // namespace armfarm

namespace armfarm {

std::vector<MetricInfoRecord> make_metric_info_records() {
  std::vector<MetricInfoRecord> records;
  for (const MetricInfo& info : metric_catalog()) {
    records.push_back({info.name, info.unit, info.meaning, to_string(info.direction), to_string(info.scope),
                       to_string(info.kind)});
  }
  return records;
}

}  // namespace armfarm
