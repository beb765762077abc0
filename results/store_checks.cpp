// Checking a database's contents row by row (`armfarm status --check`, and every merge input
// before anything is written).
#include "results/series_codec.hpp"
#include "results/store_internal.hpp"

namespace armfarm {

using namespace store_detail;

namespace {

// A query that returns (row description, problem) for each offending row.
struct RowCheck {
  const char* sql;
};

// Each query lists the rows armfarm would never have written. Storage classes are checked with
// typeof() because SQLite's column affinity accepts any value in any column.
constexpr RowCheck kRowChecks[] = {
    // Values the schema's CHECKs allow only when they were bypassed (ignore_check_constraints).
    {"SELECT 'jobs row ' || id || ' (' || key || ')', 'status ' || quote(status) || ' is not a job status' FROM jobs "
     "WHERE status IS NOT 'pending' AND status IS NOT 'running' AND status IS NOT 'done' AND status IS NOT 'failed' "
     "AND status IS NOT 'diverged' AND status IS NOT 'timeout'"},
    {"SELECT 'runs row ' || id, 'status ' || quote(status) || ' is not a run status' FROM runs "
     "WHERE status IS NOT 'running' AND status IS NOT 'complete' AND status IS NOT 'interrupted'"},
    {"SELECT 'job_claims row ' || id, 'state ' || quote(state) || ' is not a claim state' FROM job_claims "
     "WHERE state IS NOT 'live' AND state IS NOT 'interrupted'"},
    {"SELECT 'jobs row ' || id || ' (' || key || ')', 'params is not a JSON object' FROM jobs "
     "WHERE typeof(params) != 'text' OR NOT json_valid(params) OR json_type(params) != 'object'"},
    {"SELECT 'jobs row ' || id || ' (' || key || ')', 'config is not a JSON object' FROM jobs "
     "WHERE typeof(config) != 'text' OR NOT json_valid(config) OR json_type(config) != 'object'"},
    {"SELECT 'jobs row ' || id || ' (' || key || ')', 'seed, attempts, end_time or wall_seconds has the wrong type' "
     "FROM jobs WHERE typeof(seed) != 'integer' OR typeof(attempts) != 'integer' "
     "OR typeof(end_time) NOT IN ('real', 'integer', 'null') OR typeof(wall_seconds) NOT IN ('real', 'integer', 'null')"},
    {"SELECT 'sweep_jobs row (' || sweep_id || ', ' || job_id || ')', 'params is not a JSON object' FROM sweep_jobs "
     "WHERE typeof(params) != 'text' OR NOT json_valid(params) OR json_type(params) != 'object' "
     "OR typeof(position) != 'integer'"},
    {"SELECT 'sweeps row ' || id, 'name, spec or start time is not text' FROM sweeps "
     "WHERE typeof(name) != 'text' OR typeof(spec_text) != 'text' OR typeof(spec_hash) != 'text' "
     "OR typeof(started_at) != 'text'"},
    {"SELECT 'metrics of job row ' || job_id || ' (' || name || ')', "
     "'value is ' || typeof(value) || ', not a real or NULL' FROM metrics WHERE typeof(value) NOT IN ('real', 'null')"},
    {"SELECT 'metrics of job row ' || job_id || ' (' || name || ')', 'joint or checkpoint is not an integer' "
     "FROM metrics WHERE typeof(joint) NOT IN ('integer', 'null') OR typeof(checkpoint) NOT IN ('integer', 'null') "
     "OR typeof(name) != 'text'"},
    {"SELECT 'series of job row ' || job_id || ' (' || name || ')', 'columns is not a JSON array' FROM series "
     "WHERE typeof(columns) != 'text' OR NOT json_valid(columns) OR json_type(columns) != 'array'"},
    {"SELECT 'series of job row ' || job_id || ' (' || name || ')', 'rows or raw_bytes disagree with the columns' "
     "FROM series WHERE typeof(rows) != 'integer' OR typeof(raw_bytes) != 'integer' OR typeof(data) != 'blob' "
     "OR (json_valid(columns) AND raw_bytes != rows * json_array_length(columns) * 8)"},
    {"SELECT 'models of job row ' || job_id, 'kind, hash or data has the wrong type or form' FROM models "
     "WHERE typeof(kind) != 'text' OR typeof(hash) != 'text' OR hash NOT GLOB 'xxh3-128:*' OR length(hash) != 41 "
     "OR typeof(data) != 'blob' OR typeof(bytes) != 'integer'"},
};

}  // namespace

std::vector<std::string> ResultsStore::check_contents(bool integrity, std::size_t limit) const {
  std::vector<std::string> findings;
  const auto add = [&](const std::string& line) {
    if (findings.size() < limit) findings.push_back(line);
  };
  if (integrity) {
    const std::string report = check_integrity();
    if (report != "ok") add("integrity_check: " + report);
  }
  {
    SqliteStatement dangling = db_->prepare("SELECT \"table\", rowid, parent FROM pragma_foreign_key_check");
    while (dangling.step()) {
      add(dangling.column_text(0) + " row " + (dangling.is_null(1) ? std::string("?") : std::to_string(dangling.column_int(1))) +
          ": refers to a missing row of " + dangling.column_text(2));
    }
  }
  for (const RowCheck& check : kRowChecks) {
    SqliteStatement rows = db_->prepare(check.sql);
    while (rows.step()) add(rows.column_text(0) + ": " + rows.column_text(1));
  }
  // Every series blob must decode (zstd, f64 little-endian) to exactly rows × columns values.
  SqliteStatement series = db_->prepare(
      "SELECT job_id, name, rows, json_array_length(columns), data FROM series "
      "WHERE typeof(rows) = 'integer' AND typeof(data) = 'blob' AND json_valid(columns) ORDER BY job_id, name");
  while (series.step() && findings.size() < limit) {
    const std::string where = "series of job row " + std::to_string(series.column_int(0)) + " (" + series.column_text(1) + ")";
    try {
      calc_series_matrix(series.column_blob(4), static_cast<long>(series.column_int(2)),
                         static_cast<long>(series.column_int(3)), where);
    } catch (const StoreError& e) {
      add(e.what());
    }
  }
  return findings;
}

void ResultsStore::verify_file(const std::string& path) {
  const ResultsStore store = ResultsStore::open(path, Mode::read_only);
  const std::vector<std::string> findings = store.check_contents(true, 2);
  if (findings.empty()) return;
  throw StoreError(path + ": damaged armfarm database: " + findings.front() +
                   (findings.size() > 1 ? " (and more: armfarm status --check " + path + " lists them)" : ""));
}

}  // namespace armfarm
