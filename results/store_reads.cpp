// Reads: sweeps, jobs, metrics, series and what the metrics mean.
#include "results/series_codec.hpp"
#include "results/store_internal.hpp"

namespace armfarm {

using namespace store_detail;

std::vector<SweepRecord> ResultsStore::find_sweeps() const {
  SqliteStatement statement = db_->prepare(std::string("SELECT ") + kSweepColumns + " FROM sweeps ORDER BY id");
  std::vector<SweepRecord> sweeps;
  while (statement.step()) sweeps.push_back(read_sweep_row(statement));
  return sweeps;
}

std::optional<SweepRecord> ResultsStore::find_sweep(const std::string& name) const {
  SqliteStatement statement =
      db_->prepare(std::string("SELECT ") + kSweepColumns + " FROM sweeps WHERE name = ?");
  statement.bind(1, name);
  if (!statement.step()) return std::nullopt;
  return read_sweep_row(statement);
}

std::vector<JobRecord> ResultsStore::find_jobs(const std::string& sweep) const {
  SqliteStatement statement = db_->prepare(
      std::string("SELECT ") + kJobColumns +
      ", sj.params FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id "
      "WHERE s.name = ? ORDER BY sj.position, j.id");
  statement.bind(1, sweep);
  std::vector<JobRecord> jobs;
  while (statement.step()) {
    JobRecord job = read_job_row(statement, path_);
    job.params = parse_stored_json(statement.column_text(13), path_ + ": sweep " + sweep + " params");
    jobs.push_back(std::move(job));
  }
  return jobs;
}

std::optional<JobRecord> ResultsStore::find_job(const std::string& key) const {
  SqliteStatement statement = db_->prepare(std::string("SELECT ") + kJobColumns + " FROM jobs j WHERE j.key = ?");
  statement.bind(1, key);
  if (!statement.step()) return std::nullopt;
  return read_job_row(statement, path_);
}

std::vector<std::string> ResultsStore::find_job_keys(const std::string& prefix) const {
  SqliteStatement statement = db_->prepare("SELECT key FROM jobs WHERE substr(key, 1, ?) = ? ORDER BY key");
  statement.bind(1, static_cast<std::int64_t>(prefix.size())).bind(2, prefix);
  std::vector<std::string> keys;
  while (statement.step()) keys.push_back(statement.column_text(0));
  return keys;
}

std::vector<MetricRecord> ResultsStore::find_metrics(std::int64_t job_id) const {
  SqliteStatement statement =
      db_->prepare("SELECT job_id, name, joint, checkpoint, value, reason FROM metrics WHERE job_id = ? "
                   "ORDER BY name, joint, checkpoint");
  statement.bind(1, job_id);
  return read_metrics(statement);
}

std::vector<MetricRecord> ResultsStore::find_sweep_metrics(const std::string& sweep) const {
  SqliteStatement statement = db_->prepare(
      "SELECT m.job_id, m.name, m.joint, m.checkpoint, m.value, m.reason FROM metrics m "
      "JOIN sweep_jobs sj ON sj.job_id = m.job_id JOIN sweeps s ON s.id = sj.sweep_id WHERE s.name = ? "
      "ORDER BY sj.position, m.job_id, m.name, m.joint, m.checkpoint");
  statement.bind(1, sweep);
  return read_metrics(statement);
}

std::vector<std::string> ResultsStore::find_series_names(std::int64_t job_id) const {
  SqliteStatement statement = db_->prepare("SELECT name FROM series WHERE job_id = ? ORDER BY name");
  statement.bind(1, job_id);
  std::vector<std::string> names;
  while (statement.step()) names.push_back(statement.column_text(0));
  return names;
}

std::optional<SeriesRecord> ResultsStore::find_series(std::int64_t job_id, const std::string& name) const {
  SqliteStatement statement = db_->prepare(
      "SELECT columns, rows, dtype, layout, codec, data FROM series WHERE job_id = ? AND name = ?");
  statement.bind(1, job_id).bind(2, name);
  if (!statement.step()) return std::nullopt;
  const std::string where = path_ + ": series " + name + " of job " + std::to_string(job_id);
  if (statement.column_text(2) != "f64le" || statement.column_text(3) != "column-major" ||
      statement.column_text(4) != "zstd") {
    throw StoreError(where + ": unknown encoding " + statement.column_text(2) + "/" + statement.column_text(3) + "/" +
                     statement.column_text(4));
  }
  SeriesRecord series;
  series.job_id = job_id;
  series.name = name;
  const nlohmann::json columns = parse_stored_json(statement.column_text(0), where);
  if (!columns.is_array()) throw StoreError(where + ": column names are not a JSON array");
  for (const auto& column : columns) series.columns.push_back(column.is_string() ? column.get<std::string>() : column.dump());
  series.rows = calc_series_matrix(statement.column_blob(5), static_cast<long>(statement.column_int(1)),
                                   static_cast<long>(series.columns.size()), where);
  return series;
}

std::map<std::string, int> ResultsStore::count_jobs_by_status(const std::string& sweep) const {
  SqliteStatement statement = db_->prepare(
      "SELECT j.status, count(*) FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id "
      "JOIN jobs j ON j.id = sj.job_id WHERE s.name = ? GROUP BY j.status");
  statement.bind(1, sweep);
  std::map<std::string, int> counts;
  while (statement.step()) counts[statement.column_text(0)] = static_cast<int>(statement.column_int(1));
  return counts;
}

std::vector<MetricInfoRecord> ResultsStore::find_metric_info() const {
  SqliteStatement statement =
      db_->prepare("SELECT name, unit, meaning, direction, scope, kind FROM metric_info ORDER BY name");
  std::vector<MetricInfoRecord> records;
  while (statement.step()) {
    records.push_back({statement.column_text(0), statement.column_text(1), statement.column_text(2),
                       statement.column_text(3), statement.column_text(4), statement.column_text(5)});
  }
  return records;
}

}  // namespace armfarm
