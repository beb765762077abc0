// Row readers and SQL quoting shared by the store's reads, writes, views and merge.
#include "results/store_internal.hpp"

namespace armfarm {
namespace store_detail {

namespace {

// Wraps `text` in `quote`, doubling every `quote` inside (SQL's escaping for both kinds).
std::string quote_with(const std::string& text, char quote) {
  std::string quoted(1, quote);
  for (char c : text) {
    if (c == quote) quoted += quote;
    quoted += c;
  }
  return quoted + quote;
}

}  // namespace

std::string quote_identifier(const std::string& name) { return quote_with(name, '"'); }

std::string quote_literal(const std::string& text) { return quote_with(text, '\''); }

nlohmann::json parse_stored_json(const std::string& text, const std::string& where) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw StoreError(where + ": stored JSON is not valid: " + e.what());
  }
}

std::vector<std::string> find_sweep_names(SqliteConnection& db) {
  SqliteStatement statement = db.prepare("SELECT name FROM sweeps ORDER BY id");
  std::vector<std::string> names;
  while (statement.step()) names.push_back(statement.column_text(0));
  return names;
}

JobRecord read_job_row(const SqliteStatement& row, const std::string& where) {
  // Column order of kJobColumns.
  JobRecord job;
  job.id = row.column_int(0);
  job.key = row.column_text(1);
  job.sweep = row.column_text(2);
  job.params = parse_stored_json(row.column_text(3), where + ": job " + job.key + " params");
  job.config = parse_stored_json(row.column_text(4), where + ": job " + job.key + " config");
  job.status = row.column_text(5);
  job.message = row.column_text(6);
  job.seed = row.column_int(7);
  job.end_time = row.column_optional_double(8);
  job.wall_seconds = row.column_optional_double(9);
  job.started_at = row.column_optional_text(10);
  job.finished_at = row.column_optional_text(11);
  job.attempts = static_cast<int>(row.column_int(12));
  return job;
}

SweepRecord read_sweep_row(const SqliteStatement& row) {
  SweepRecord sweep;
  sweep.id = row.column_int(0);
  sweep.name = row.column_text(1);
  sweep.description = row.column_text(2);
  sweep.spec_text = row.column_text(3);
  sweep.spec_hash = row.column_text(4);
  sweep.started_at = row.column_text(5);
  sweep.finished_at = row.column_optional_text(6);
  sweep.provenance.armfarm_version = row.column_text(7);
  sweep.provenance.git_commit = row.column_text(8);
  sweep.provenance.git_dirty = !row.is_null(9) && row.column_int(9) != 0;
  sweep.provenance.compiler = row.column_text(10);
  sweep.provenance.simbody_version = row.column_text(11);
  sweep.provenance.host = row.column_text(12);
  return sweep;
}

std::vector<MetricRecord> read_metrics(SqliteStatement& statement) {
  std::vector<MetricRecord> metrics;
  while (statement.step()) {
    MetricRecord metric;
    metric.job_id = statement.column_int(0);
    metric.name = statement.column_text(1);
    if (!statement.is_null(2)) metric.joint = static_cast<int>(statement.column_int(2));
    if (!statement.is_null(3)) metric.checkpoint = statement.column_int(3);
    metric.value = statement.column_optional_double(4);
    metric.reason = statement.column_optional_text(5).value_or("");
    metrics.push_back(std::move(metric));
  }
  return metrics;
}

}  // namespace store_detail
}  // namespace armfarm
