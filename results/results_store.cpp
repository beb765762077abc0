#include "results/results_store.hpp"

#include "results/series_codec.hpp"
#include "results/sqlite_connection.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <set>
#include <sstream>
#include <unistd.h>

namespace armfarm {
namespace {

constexpr std::int64_t kApplicationId = 0x41524D46;  // "ARMF"

// Migration k (1-based) moves the schema from version k-1 to k. Never edit a released entry;
// append a new one.
const std::vector<const char*>& migrations() {
  static const std::vector<const char*> scripts = {
      // 1: the initial schema.
      R"sql(
CREATE TABLE sweeps (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL UNIQUE,
  description TEXT NOT NULL DEFAULT '',
  spec_text TEXT NOT NULL,
  spec_hash TEXT NOT NULL,
  started_at TEXT NOT NULL,
  finished_at TEXT,
  armfarm_version TEXT, git_commit TEXT, git_dirty INTEGER, compiler TEXT, simbody_version TEXT, host TEXT
);
CREATE TABLE runs (
  id INTEGER PRIMARY KEY,
  sweep_id INTEGER NOT NULL REFERENCES sweeps(id) ON DELETE CASCADE,
  started_at TEXT NOT NULL,
  finished_at TEXT,
  status TEXT NOT NULL CHECK (status IN ('running', 'complete', 'interrupted')),
  shard TEXT,
  jobs_total INTEGER NOT NULL,
  jobs_skipped INTEGER,
  jobs_run INTEGER,
  armfarm_version TEXT, git_commit TEXT, host TEXT
);
CREATE TABLE jobs (
  id INTEGER PRIMARY KEY,
  key TEXT NOT NULL UNIQUE,
  sweep TEXT NOT NULL,
  params TEXT NOT NULL,
  config TEXT NOT NULL,
  status TEXT NOT NULL CHECK (status IN ('pending', 'running', 'done', 'failed', 'diverged', 'timeout')),
  message TEXT,
  seed INTEGER NOT NULL,
  end_time REAL,
  wall_seconds REAL,
  started_at TEXT,
  finished_at TEXT,
  attempts INTEGER NOT NULL DEFAULT 0
);
CREATE TABLE sweep_jobs (
  sweep_id INTEGER NOT NULL REFERENCES sweeps(id) ON DELETE CASCADE,
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  params TEXT NOT NULL,
  PRIMARY KEY (sweep_id, job_id)
);
CREATE INDEX sweep_jobs_by_job ON sweep_jobs(job_id);
CREATE TABLE metrics (
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  joint INTEGER,
  value REAL
);
CREATE UNIQUE INDEX metrics_by_job ON metrics(job_id, name, IFNULL(joint, 0));
CREATE INDEX metrics_by_name ON metrics(name, joint);
CREATE TABLE series (
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  columns TEXT NOT NULL,
  rows INTEGER NOT NULL,
  dtype TEXT NOT NULL DEFAULT 'f64le',
  layout TEXT NOT NULL DEFAULT 'column-major',
  codec TEXT NOT NULL DEFAULT 'zstd',
  raw_bytes INTEGER NOT NULL,
  data BLOB NOT NULL,
  PRIMARY KEY (job_id, name)
);
CREATE VIEW job_metrics AS
  SELECT s.name AS sweep, j.id AS job_id, j.key AS key, j.status AS status, j.seed AS seed,
         sj.params AS params, m.name AS name, m.joint AS joint, m.value AS value
    FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id
    JOIN metrics m ON m.job_id = j.id;
CREATE VIEW sweep_job_status AS
  SELECT s.name AS sweep, j.id AS job_id, j.key AS key, j.status AS status, j.message AS message,
         j.seed AS seed, sj.params AS params, j.wall_seconds AS wall_seconds, j.end_time AS end_time
    FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id;
)sql",
      // 2: metrics gain checkpoint and reason, values must be REAL or NULL; metric_info explains names.
      R"sql(
DROP VIEW job_metrics;
CREATE TABLE metrics_v2 (
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  joint INTEGER,
  checkpoint INTEGER,
  value REAL CHECK (typeof(value) IN ('real', 'null')),
  reason TEXT
);
INSERT INTO metrics_v2 (job_id, name, joint, checkpoint, value, reason)
  SELECT job_id, name, joint, NULL, CAST(value AS REAL),
         CASE WHEN value IS NULL THEN 'undefined (schema version 1 kept no reason)' END
    FROM metrics;
DROP TABLE metrics;
ALTER TABLE metrics_v2 RENAME TO metrics;
CREATE UNIQUE INDEX metrics_by_job ON metrics(job_id, name, IFNULL(joint, 0), IFNULL(checkpoint, -1));
CREATE INDEX metrics_by_name ON metrics(name, joint);
CREATE TABLE metric_info (
  name TEXT PRIMARY KEY,
  unit TEXT NOT NULL,
  meaning TEXT NOT NULL,
  direction TEXT NOT NULL CHECK (direction IN ('lower', 'higher', 'none')),
  scope TEXT NOT NULL CHECK (scope IN ('job', 'joint', 'task_axis', 'segment', 'checkpoint')),
  kind TEXT NOT NULL CHECK (kind IN ('result', 'timing', 'diagnostic'))
);
CREATE VIEW job_metrics AS
  SELECT s.name AS sweep, j.id AS job_id, j.key AS key, j.status AS status, j.seed AS seed,
         sj.params AS params, m.name AS name, m.joint AS joint, m.checkpoint AS checkpoint, m.value AS value,
         m.reason AS reason, i.unit AS unit, i.direction AS direction, i.kind AS kind
    FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id
    JOIN metrics m ON m.job_id = j.id LEFT JOIN metric_info i ON i.name = m.name;
)sql",
  };
  return scripts;
}

std::string quote_identifier(const std::string& name) {
  std::string quoted = "\"";
  for (char c : name) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string quote_literal(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'') quoted += '\'';
    quoted += c;
  }
  return quoted + "'";
}

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

void write_sweep_view(SqliteConnection& db, const std::string& sweep);

// Applies the migrations after `version` in one transaction. The generated per-sweep views are
// dropped first (they name columns of the old tables) and written anew afterwards.
void migrate(SqliteConnection& db, std::int64_t version) {
  SqliteTransaction transaction(db);
  if (version >= 1) {
    std::vector<std::string> views;
    SqliteStatement statement = db.prepare(
        "SELECT name FROM sqlite_master WHERE type = 'view' AND name NOT IN ('job_metrics', 'sweep_job_status')");
    while (statement.step()) views.push_back(statement.column_text(0));
    for (const std::string& view : views) db.execute("DROP VIEW " + quote_identifier(view));
  }
  for (std::int64_t k = version; k < kResultsSchemaVersion; ++k) db.execute(migrations()[static_cast<std::size_t>(k)]);
  db.execute("PRAGMA application_id = " + std::to_string(kApplicationId));
  db.execute("PRAGMA user_version = " + std::to_string(kResultsSchemaVersion));
  if (version >= 1) {
    for (const std::string& sweep : find_sweep_names(db)) write_sweep_view(db, sweep);
  }
  transaction.commit();
}

// Opens the file and checks it is an armfarm database this build can read; migrates when writable.
std::unique_ptr<SqliteConnection> open_checked(const std::string& path, ResultsStore::Mode mode) {
  const bool read_only = mode == ResultsStore::Mode::read_only;
  if (read_only && !std::filesystem::exists(path)) throw StoreError(path + ": no such database file");
  if (std::filesystem::is_directory(path)) throw StoreError(path + ": is a directory, not a database file");
  auto db = std::make_unique<SqliteConnection>(path, read_only);

  std::int64_t application_id = 0, version = 0, n_tables = 0;
  try {
    application_id = db->query_int("PRAGMA application_id");
    version = db->query_int("PRAGMA user_version");
    n_tables = db->query_int("SELECT count(*) FROM sqlite_master");
  } catch (const StoreError& e) {
    throw StoreError(path + ": not a readable SQLite database (" + std::string(e.what()).substr(path.size() + 2) +
                     ")");
  }
  const bool fresh = application_id == 0 && version == 0 && n_tables == 0;
  if (!fresh && application_id != kApplicationId) {
    throw StoreError(path + ": an SQLite database, but not an armfarm results database");
  }
  if (version > kResultsSchemaVersion) {
    throw StoreError(path + ": written by a newer armfarm (schema version " + std::to_string(version) +
                     "; this build reads up to version " + std::to_string(kResultsSchemaVersion) + ")");
  }
  if (read_only) {
    if (fresh) throw StoreError(path + ": empty file, not an armfarm results database");
    if (version < kResultsSchemaVersion) {
      // An older file is read through a migrated in-memory copy; the file stays as it is.
      db.reset();
      db = SqliteConnection::make_memory_copy(path);
      migrate(*db, version);
    }
    db->execute("PRAGMA foreign_keys = ON");
    return db;
  }

  db->execute("PRAGMA journal_mode = WAL");
  db->execute("PRAGMA synchronous = NORMAL");
  db->execute("PRAGMA foreign_keys = ON");
  if (version < kResultsSchemaVersion) migrate(*db, version);
  return db;
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

constexpr const char* kJobColumns =
    "j.id, j.key, j.sweep, j.params, j.config, j.status, j.message, j.seed, j.end_time, j.wall_seconds, "
    "j.started_at, j.finished_at, j.attempts";

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
  sweep.provenance.git_dirty = row.column_int(9) != 0;
  sweep.provenance.compiler = row.column_text(10);
  sweep.provenance.simbody_version = row.column_text(11);
  sweep.provenance.host = row.column_text(12);
  return sweep;
}

constexpr const char* kSweepColumns =
    "id, name, description, spec_text, spec_hash, started_at, finished_at, armfarm_version, git_commit, git_dirty, "
    "compiler, simbody_version, host";

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

void upsert_metric_info_rows(SqliteConnection& db, const std::vector<MetricInfoRecord>& records) {
  SqliteStatement statement = db.prepare(
      "INSERT INTO metric_info (name, unit, meaning, direction, scope, kind) VALUES (?1, ?2, ?3, ?4, ?5, ?6) "
      "ON CONFLICT(name) DO UPDATE SET unit = ?2, meaning = ?3, direction = ?4, scope = ?5, kind = ?6");
  for (const MetricInfoRecord& r : records) {
    statement.bind(1, r.name).bind(2, r.unit).bind(3, r.meaning).bind(4, r.direction).bind(5, r.scope).bind(6, r.kind);
    statement.execute();
  }
}

void insert_metrics_and_series(SqliteConnection& db, std::int64_t job_id, const JobResultRecord& result) {
  db.prepare("DELETE FROM metrics WHERE job_id = ?").bind(1, job_id).execute();
  db.prepare("DELETE FROM series WHERE job_id = ?").bind(1, job_id).execute();
  SqliteStatement metric =
      db.prepare("INSERT INTO metrics (job_id, name, joint, checkpoint, value, reason) VALUES (?, ?, ?, ?, ?, ?)");
  for (const MetricRecord& m : result.metrics) {
    metric.bind(1, job_id)
        .bind(2, m.name)
        .bind(3, m.joint ? std::optional<std::int64_t>(*m.joint) : std::nullopt)
        .bind(4, m.checkpoint);
    std::string reason = m.reason;
    if (m.value && std::isfinite(*m.value)) {
      metric.bind(5, *m.value);
    } else {
      // SQLite has no NaN; infinities would not survive JSON exports either.
      metric.bind_null(5);
      if (reason.empty()) reason = m.value ? "not finite" : "undefined";
    }
    metric.bind(6, reason.empty() ? std::optional<std::string>() : std::optional<std::string>(reason));
    metric.execute();
  }
  SqliteStatement series = db.prepare(
      "INSERT INTO series (job_id, name, columns, rows, raw_bytes, data) VALUES (?, ?, ?, ?, ?, ?)");
  for (const SeriesRecord& s : result.series) {
    if (static_cast<std::size_t>(s.rows.cols()) != s.columns.size()) {
      throw StoreError(db.path() + ": series " + s.name + " of job " + result.key + " has " +
                       std::to_string(s.rows.cols()) + " columns but " + std::to_string(s.columns.size()) +
                       " column names");
    }
    series.bind(1, job_id)
        .bind(2, s.name)
        .bind(3, nlohmann::json(s.columns).dump())
        .bind(4, static_cast<std::int64_t>(s.rows.rows()))
        .bind(5, static_cast<std::int64_t>(s.rows.size() * sizeof(double)))
        .bind(6, calc_series_blob(s.rows))
        .execute();
  }
}

}  // namespace

std::string make_sweep_view_name(const std::string& sweep) {
  std::string name = "sweep_";
  bool replaced = false;
  for (char c : sweep) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    name += keep ? c : '_';
    replaced = replaced || !keep;
  }
  if (replaced) {
    std::uint64_t hash = 14695981039346656037ull;  // FNV-1a, 64 bit
    for (unsigned char c : sweep) hash = (hash ^ c) * 1099511628211ull;
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "_%06llx", static_cast<unsigned long long>(hash & 0xFFFFFFull));
    name += suffix;
  }
  return name;
}

std::string make_utc_timestamp() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto millis =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%S", &utc);
  char result[40];
  std::snprintf(result, sizeof result, "%s.%03dZ", buffer, static_cast<int>(millis));
  return result;
}

ResultsStore::ResultsStore(std::string path, std::unique_ptr<SqliteConnection> connection)
    : path_(std::move(path)), db_(std::move(connection)) {}
ResultsStore::ResultsStore(ResultsStore&&) noexcept = default;
ResultsStore& ResultsStore::operator=(ResultsStore&&) noexcept = default;
ResultsStore::~ResultsStore() = default;

ResultsStore ResultsStore::open(const std::string& path, Mode mode) {
  return ResultsStore(path, open_checked(path, mode));
}

int ResultsStore::schema_version() const { return static_cast<int>(db_->query_int("PRAGMA user_version")); }

std::string ResultsStore::check_integrity() const {
  SqliteStatement statement = db_->prepare("PRAGMA integrity_check");
  std::string findings;
  while (statement.step()) findings += (findings.empty() ? "" : "\n") + statement.column_text(0);
  return findings;
}

// ---- reads ----

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

// ---- writes ----

RegisteredRun ResultsStore::insert_sweep_run(const SweepRegistration& sweep, const std::vector<JobRegistration>& jobs) {
  SqliteTransaction transaction(*db_);
  const Provenance& p = sweep.provenance;
  db_->prepare(
         "INSERT INTO sweeps (name, description, spec_text, spec_hash, started_at, armfarm_version, git_commit, "
         "git_dirty, compiler, simbody_version, host) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11) "
         "ON CONFLICT(name) DO UPDATE SET description = ?2, spec_text = ?3, spec_hash = ?4, finished_at = NULL, "
         "armfarm_version = ?6, git_commit = ?7, git_dirty = ?8, compiler = ?9, simbody_version = ?10, host = ?11")
      .bind(1, sweep.name)
      .bind(2, sweep.description)
      .bind(3, sweep.spec_text)
      .bind(4, sweep.spec_hash)
      .bind(5, sweep.started_at)
      .bind(6, p.armfarm_version)
      .bind(7, p.git_commit)
      .bind(8, static_cast<std::int64_t>(p.git_dirty))
      .bind(9, p.compiler)
      .bind(10, p.simbody_version)
      .bind(11, p.host)
      .execute();
  RegisteredRun run;
  {
    SqliteStatement id = db_->prepare("SELECT id FROM sweeps WHERE name = ?");
    id.bind(1, sweep.name);
    id.step();
    run.sweep_id = id.column_int(0);
  }
  if (!sweep.shard) db_->prepare("DELETE FROM sweep_jobs WHERE sweep_id = ?").bind(1, run.sweep_id).execute();
  upsert_metric_info_rows(*db_, sweep.metric_info);

  SqliteStatement insert_job = db_->prepare(
      "INSERT INTO jobs (key, sweep, params, config, status, seed) VALUES (?, ?, ?, ?, 'pending', ?) "
      "ON CONFLICT(key) DO NOTHING");
  SqliteStatement find_job = db_->prepare("SELECT id, status FROM jobs WHERE key = ?");
  SqliteStatement insert_member = db_->prepare(
      "INSERT INTO sweep_jobs (sweep_id, job_id, position, params) VALUES (?1, ?2, ?3, ?4) "
      "ON CONFLICT(sweep_id, job_id) DO UPDATE SET position = ?3, params = ?4");
  std::int64_t position = 0;
  for (const JobRegistration& job : jobs) {
    const std::string params = job.params.dump();
    insert_job.bind(1, job.key).bind(2, sweep.name).bind(3, params).bind(4, job.config.dump()).bind(5, job.seed);
    insert_job.execute();
    find_job.bind(1, job.key);
    if (!find_job.step()) throw StoreError(path_ + ": job " + job.key + " missing after insert");
    const std::int64_t job_id = find_job.column_int(0);
    run.status_by_key[job.key] = find_job.column_text(1);
    find_job.reset();
    insert_member.bind(1, run.sweep_id).bind(2, job_id).bind(3, position++).bind(4, params).execute();
  }

  db_->prepare(
         "INSERT INTO runs (sweep_id, started_at, status, shard, jobs_total, armfarm_version, git_commit, host) "
         "VALUES (?, ?, 'running', ?, ?, ?, ?, ?)")
      .bind(1, run.sweep_id)
      .bind(2, sweep.started_at)
      .bind(3, sweep.shard)
      .bind(4, static_cast<std::int64_t>(jobs.size()))
      .bind(5, p.armfarm_version)
      .bind(6, p.git_commit)
      .bind(7, p.host)
      .execute();
  run.run_id = db_->last_insert_rowid();
  transaction.commit();
  return run;
}

void ResultsStore::insert_job_batch(const JobBatch& batch, const std::string& sweep_name) {
  SqliteTransaction transaction(*db_);
  if (!batch.started.empty()) {
    SqliteStatement started = db_->prepare(
        "UPDATE jobs SET status = 'running', attempts = attempts + 1, sweep = ?, started_at = ?, finished_at = NULL "
        "WHERE key = ?");
    const std::string now = make_utc_timestamp();
    for (const std::string& key : batch.started) started.bind(1, sweep_name).bind(2, now).bind(3, key).execute();
  }
  SqliteStatement finished = db_->prepare(
      "UPDATE jobs SET status = ?, message = ?, end_time = ?, wall_seconds = ?, started_at = ?, finished_at = ?, "
      "sweep = ? WHERE key = ? RETURNING id");
  for (const JobResultRecord& result : batch.finished) {
    finished.bind(1, result.status)
        .bind(2, result.message.empty() ? std::optional<std::string>() : std::optional<std::string>(result.message))
        .bind(3, result.end_time)
        .bind(4, result.wall_seconds)
        .bind(5, result.started_at)
        .bind(6, result.finished_at)
        .bind(7, sweep_name)
        .bind(8, result.key);
    if (!finished.step()) throw StoreError(path_ + ": job " + result.key + " is not registered");
    const std::int64_t job_id = finished.column_int(0);
    finished.reset();
    insert_metrics_and_series(*db_, job_id, result);
  }
  if (!batch.abandoned.empty()) {
    SqliteStatement abandoned =
        db_->prepare("UPDATE jobs SET status = 'pending' WHERE key = ? AND status = 'running'");
    for (const std::string& key : batch.abandoned) abandoned.bind(1, key).execute();
  }
  transaction.commit();
}

void ResultsStore::update_run_finished(std::int64_t run_id, const std::string& status, int jobs_run, int jobs_skipped,
                                       const std::string& finished_at) {
  std::string sweep_name;
  {
    SqliteTransaction transaction(*db_);
    db_->prepare("UPDATE runs SET status = ?, jobs_run = ?, jobs_skipped = ?, finished_at = ? WHERE id = ?")
        .bind(1, status)
        .bind(2, jobs_run)
        .bind(3, jobs_skipped)
        .bind(4, finished_at)
        .bind(5, run_id)
        .execute();
    if (status == "complete") {
      db_->prepare("UPDATE sweeps SET finished_at = ? WHERE id = (SELECT sweep_id FROM runs WHERE id = ?)")
          .bind(1, finished_at)
          .bind(2, run_id)
          .execute();
    }
    SqliteStatement name =
        db_->prepare("SELECT s.name FROM sweeps s JOIN runs r ON r.sweep_id = s.id WHERE r.id = ?");
    name.bind(1, run_id);
    if (!name.step()) throw StoreError(path_ + ": no run " + std::to_string(run_id));
    sweep_name = name.column_text(0);
    transaction.commit();
  }
  update_sweep_view(sweep_name);
}

namespace {

void write_sweep_view(SqliteConnection& db, const std::string& sweep) {
  // Columns: the sweep's varying parameters, then its metrics (name, or name_j<joint>).
  std::set<std::string> param_names;
  {
    SqliteStatement statement = db.prepare(
        "SELECT DISTINCT e.key FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id, json_each(sj.params) e "
        "WHERE s.name = ? ORDER BY e.key");
    statement.bind(1, sweep);
    while (statement.step()) param_names.insert(statement.column_text(0));
  }
  struct MetricColumn {
    std::string name;
    std::optional<std::int64_t> joint, checkpoint;
  };
  std::vector<MetricColumn> metric_columns;
  {
    SqliteStatement statement = db.prepare(
        "SELECT DISTINCT m.name, m.joint, m.checkpoint FROM metrics m JOIN sweep_jobs sj ON sj.job_id = m.job_id "
        "JOIN sweeps s ON s.id = sj.sweep_id WHERE s.name = ? ORDER BY m.name, m.joint, m.checkpoint");
    statement.bind(1, sweep);
    while (statement.step()) {
      MetricColumn column{statement.column_text(0), std::nullopt, std::nullopt};
      if (!statement.is_null(1)) column.joint = statement.column_int(1);
      if (!statement.is_null(2)) column.checkpoint = statement.column_int(2);
      metric_columns.push_back(std::move(column));
    }
  }
  std::set<std::string> used = {"job_id", "key", "status", "seed", "message"};
  std::ostringstream sql;
  const std::string view = make_sweep_view_name(sweep);
  sql << "CREATE VIEW " << quote_identifier(view)
      << " AS SELECT j.id AS job_id, j.key AS key, j.status AS status, j.seed AS seed, j.message AS message";
  for (const std::string& param : param_names) {
    if (param.find('"') != std::string::npos || !used.insert(param).second) continue;
    sql << ", json_extract(sj.params, " << quote_literal("$.\"" + param + "\"") << ") AS " << quote_identifier(param);
  }
  for (const MetricColumn& metric : metric_columns) {
    std::string column = metric.name;
    if (metric.joint) column += "_j" + std::to_string(*metric.joint);
    if (metric.checkpoint) column += "_c" + std::to_string(*metric.checkpoint);
    if (!used.insert(column).second) continue;
    const auto match = [](const std::optional<std::int64_t>& value) {
      return value ? "= " + std::to_string(*value) : std::string("IS NULL");
    };
    sql << ", (SELECT m.value FROM metrics m WHERE m.job_id = j.id AND m.name = " << quote_literal(metric.name)
        << " AND m.joint " << match(metric.joint) << " AND m.checkpoint " << match(metric.checkpoint) << ") AS "
        << quote_identifier(column);
  }
  sql << " FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id WHERE s.name = "
      << quote_literal(sweep) << " ORDER BY sj.position";
  db.execute("DROP VIEW IF EXISTS " + quote_identifier(view));
  db.execute(sql.str());
}

}  // namespace

void ResultsStore::update_sweep_view(const std::string& sweep) {
  SqliteTransaction transaction(*db_);
  write_sweep_view(*db_, sweep);
  transaction.commit();
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

void ResultsStore::upsert_metric_info(const std::vector<MetricInfoRecord>& records) {
  SqliteTransaction transaction(*db_);
  upsert_metric_info_rows(*db_, records);
  transaction.commit();
}

MergeReport ResultsStore::merge_from(const std::string& other_path) {
  // Checks the other file is an armfarm database this build reads before touching anything;
  // an older schema is merged from a migrated temporary copy (the file itself is only read).
  std::int64_t other_version = 0;
  {
    ResultsStore other = ResultsStore::open(other_path, Mode::read_only);
    other_version = SqliteConnection(other_path, true).query_int("PRAGMA user_version");
  }
  struct TemporaryCopy {
    std::string path;
    ~TemporaryCopy() {
      if (path.empty()) return;
      std::error_code ignored;
      for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix, ignored);
    }
  } copy;
  std::string attached_path = other_path;
  if (other_version < kResultsSchemaVersion) {
    std::string pattern = (std::filesystem::temp_directory_path() / "armfarm-merge-XXXXXX").string();
    const int fd = mkstemp(pattern.data());
    if (fd < 0) throw StoreError(other_path + ": cannot create a temporary copy to migrate");
    close(fd);
    std::filesystem::remove(pattern);
    copy.path = pattern;
    SqliteConnection(other_path, true).copy_to_file(copy.path);
    { ResultsStore migrated = ResultsStore::open(copy.path, Mode::read_write); }
    attached_path = copy.path;
  }
  MergeReport report;
  db_->prepare("ATTACH DATABASE ? AS src").bind(1, attached_path).execute();
  struct Detach {
    SqliteConnection& db;
    ~Detach() {
      try {
        db.execute("DETACH DATABASE src");
      } catch (const StoreError&) {
      }
    }
  } detach{*db_};

  std::set<std::string> touched_sweeps;
  {
    SqliteTransaction transaction(*db_);
    // Sweeps: new ones are copied; a sweep of the same name must have the same spec.
    std::map<std::int64_t, std::int64_t> sweep_id_map;  // src id -> main id
    SqliteStatement src_sweeps = db_->prepare(std::string("SELECT ") + kSweepColumns + " FROM src.sweeps ORDER BY id");
    while (src_sweeps.step()) {
      const SweepRecord sweep = read_sweep_row(src_sweeps);
      touched_sweeps.insert(sweep.name);
      SqliteStatement mine = db_->prepare("SELECT id, spec_hash FROM main.sweeps WHERE name = ?");
      mine.bind(1, sweep.name);
      if (mine.step()) {
        sweep_id_map[sweep.id] = mine.column_int(0);
        if (mine.column_text(1) != sweep.spec_hash) {
          report.conflicts.push_back("sweep " + sweep.name + ": different specs (hash " + mine.column_text(1) +
                                     " here, " + sweep.spec_hash + " in " + other_path + ")");
        }
        db_->prepare("UPDATE main.sweeps SET started_at = min(started_at, ?) WHERE id = ?")
            .bind(1, sweep.started_at)
            .bind(2, sweep_id_map[sweep.id])
            .execute();
      } else {
        db_->prepare(std::string("INSERT INTO main.sweeps (") + kSweepColumns + ") SELECT NULL, " +
                     std::string(kSweepColumns).substr(4) + " FROM src.sweeps WHERE id = ?")
            .bind(1, sweep.id)
            .execute();
        sweep_id_map[sweep.id] = db_->last_insert_rowid();
      }
      db_->prepare(
             "INSERT INTO main.runs (sweep_id, started_at, finished_at, status, shard, jobs_total, jobs_skipped, "
             "jobs_run, armfarm_version, git_commit, host) SELECT ?, started_at, finished_at, status, shard, "
             "jobs_total, jobs_skipped, jobs_run, armfarm_version, git_commit, host FROM src.runs WHERE sweep_id = ?")
          .bind(1, sweep_id_map[sweep.id])
          .bind(2, sweep.id)
          .execute();
    }

    // What the metrics mean: the other file's entries for names this file does not know.
    db_->execute("INSERT INTO main.metric_info SELECT * FROM src.metric_info WHERE true ON CONFLICT(name) DO NOTHING");
    // Timing and diagnostic metrics vary from run to run: never a conflict.
    std::set<std::string> not_results;
    {
      SqliteStatement statement = db_->prepare(
          "SELECT name FROM main.metric_info WHERE kind != 'result' UNION SELECT name FROM src.metric_info "
          "WHERE kind != 'result'");
      while (statement.step()) not_results.insert(statement.column_text(0));
    }

    // Jobs: compare by key.
    auto metrics_of = [&](const std::string& schema, std::int64_t job_id) {
      SqliteStatement statement = db_->prepare("SELECT job_id, name, joint, checkpoint, value, reason FROM " + schema +
                                               ".metrics WHERE job_id = ? ORDER BY name, joint, checkpoint");
      statement.bind(1, job_id);
      std::vector<MetricRecord> results;
      for (MetricRecord& metric : read_metrics(statement)) {
        if (!not_results.count(metric.name)) results.push_back(std::move(metric));
      }
      return results;
    };
    auto series_of = [&](const std::string& schema, std::int64_t job_id) {
      SqliteStatement statement = db_->prepare("SELECT name, columns, rows, dtype, layout, data FROM " + schema +
                                               ".series WHERE job_id = ? ORDER BY name");
      statement.bind(1, job_id);
      // Name, column names, encoding and the decoded bytes (compared bit for bit, NaN included).
      std::vector<std::string> all;
      while (statement.step()) {
        const auto n_columns = static_cast<long>(parse_stored_json(statement.column_text(1), other_path).size());
        const Eigen::MatrixXd rows =
            calc_series_matrix(statement.column_blob(5), static_cast<long>(statement.column_int(2)), n_columns,
                               schema == "src" ? other_path : path_);
        all.push_back(statement.column_text(0) + "\n" + statement.column_text(1) + "\n" + statement.column_text(3) +
                      statement.column_text(4) + "\n" +
                      std::string(reinterpret_cast<const char*>(rows.data()), rows.size() * sizeof(double)));
      }
      return all;
    };
    auto copy_results = [&](std::int64_t src_id, std::int64_t main_id) {
      db_->prepare("DELETE FROM main.metrics WHERE job_id = ?").bind(1, main_id).execute();
      db_->prepare("DELETE FROM main.series WHERE job_id = ?").bind(1, main_id).execute();
      db_->prepare("INSERT INTO main.metrics (job_id, name, joint, checkpoint, value, reason) "
                   "SELECT ?, name, joint, checkpoint, value, reason FROM src.metrics WHERE job_id = ?")
          .bind(1, main_id)
          .bind(2, src_id)
          .execute();
      db_->prepare("INSERT INTO main.series (job_id, name, columns, rows, dtype, layout, codec, raw_bytes, data) "
                   "SELECT ?, name, columns, rows, dtype, layout, codec, raw_bytes, data FROM src.series WHERE job_id = ?")
          .bind(1, main_id)
          .bind(2, src_id)
          .execute();
    };
    constexpr const char* kCopiedColumns =
        "sweep, params, config, status, message, seed, end_time, wall_seconds, started_at, finished_at, attempts";

    std::map<std::int64_t, std::int64_t> job_id_map;
    SqliteStatement src_jobs = db_->prepare("SELECT id, key, status FROM src.jobs ORDER BY id");
    while (src_jobs.step()) {
      const std::int64_t src_id = src_jobs.column_int(0);
      const std::string key = src_jobs.column_text(1);
      const std::string src_status = src_jobs.column_text(2);
      SqliteStatement mine = db_->prepare("SELECT id, status FROM main.jobs WHERE key = ?");
      mine.bind(1, key);
      if (!mine.step()) {
        db_->prepare(std::string("INSERT INTO main.jobs (key, ") + kCopiedColumns + ") SELECT key, " + kCopiedColumns +
                     " FROM src.jobs WHERE id = ?")
            .bind(1, src_id)
            .execute();
        job_id_map[src_id] = db_->last_insert_rowid();
        copy_results(src_id, job_id_map[src_id]);
        ++report.jobs_added;
        continue;
      }
      const std::int64_t main_id = mine.column_int(0);
      const std::string main_status = mine.column_text(1);
      job_id_map[src_id] = main_id;
      if (src_status != "done" && main_status == "done") {
        ++report.jobs_identical;  // nothing new in the other file: keep the finished job
        continue;
      }
      if (src_status == "done" && main_status != "done") {
        db_->prepare(std::string("UPDATE main.jobs SET (") + kCopiedColumns + ") = (SELECT " + kCopiedColumns +
                     " FROM src.jobs WHERE id = ?) WHERE id = ?")
            .bind(1, src_id)
            .bind(2, main_id)
            .execute();
        copy_results(src_id, main_id);
        ++report.jobs_replaced;
        continue;
      }
      const auto main_metrics = metrics_of("main", main_id), src_metrics = metrics_of("src", src_id);
      bool same = main_status == src_status && main_metrics.size() == src_metrics.size();
      for (std::size_t i = 0; same && i < main_metrics.size(); ++i) {
        const MetricRecord &a = main_metrics[i], &b = src_metrics[i];
        same = a.name == b.name && a.joint == b.joint && a.checkpoint == b.checkpoint && a.value == b.value &&
               a.reason == b.reason;
      }
      if (same) same = series_of("main", main_id) == series_of("src", src_id);
      if (same) {
        ++report.jobs_identical;
      } else {
        report.conflicts.push_back("job " + key + ": different results (" + main_status + " here, " + src_status +
                                   " in " + other_path + "); kept this file's");
      }
    }

    // Memberships.
    SqliteStatement members = db_->prepare("SELECT sweep_id, job_id, position, params FROM src.sweep_jobs");
    SqliteStatement insert_member = db_->prepare(
        "INSERT INTO main.sweep_jobs (sweep_id, job_id, position, params) VALUES (?, ?, ?, ?) "
        "ON CONFLICT(sweep_id, job_id) DO NOTHING");
    while (members.step()) {
      insert_member.bind(1, sweep_id_map.at(members.column_int(0)))
          .bind(2, job_id_map.at(members.column_int(1)))
          .bind(3, members.column_int(2))
          .bind(4, members.column_text(3))
          .execute();
    }
    transaction.commit();
  }
  for (const std::string& sweep : touched_sweeps) update_sweep_view(sweep);
  return report;
}

}  // namespace armfarm
