// The schema: migrations, and opening a file with its checks. Schema documented in results/README.md.
#include "results/store_internal.hpp"

#include "results/job_claims.hpp"
#include "results/search_store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <thread>

namespace armfarm {
namespace store_detail {

namespace {

// 1: the initial schema: sweeps, runs, jobs, their sweeps, metrics, series, two fixed views.
const char* const kInitialSchema = R"sql(
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
)sql";

// 2: metrics gain checkpoint and reason, values must be REAL or NULL; metric_info explains names.
const char* const kMetricCheckpointsMigration = R"sql(
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
)sql";

// 4: models holds the learned model a job stored (learning.store_model), its model file as a BLOB.
const char* const kModelsMigration = R"sql(
CREATE TABLE models (
  job_id INTEGER PRIMARY KEY REFERENCES jobs(id) ON DELETE CASCADE,
  kind TEXT NOT NULL,
  hash TEXT NOT NULL,
  bytes INTEGER NOT NULL CHECK (bytes = length(data)),
  data BLOB NOT NULL
);
CREATE INDEX models_by_hash ON models(hash);
)sql";

}  // namespace

// Migration k (1-based) moves the schema from version k-1 to k. Never edit a released entry;
// append a new one.
const std::vector<const char*>& migrations() {
  static const std::vector<const char*> scripts = {
      kInitialSchema,                     // 1
      kMetricCheckpointsMigration,        // 2: metric checkpoints and reasons, metric_info
      job_claims_sql::kMigration,         // 3: runners' job claims, runs' heartbeats (job_claims.cpp)
      kModelsMigration,                   // 4: the learned models jobs stored
      job_claims_sql::kFencingMigration,  // 5: the file's lease, claims' fencing tokens (job_claims.cpp)
      search_store_sql::kMigration,       // 6: searches, rungs, trials, steps, objectives (search_store.cpp)
      // 7: the settings a search decision depends on beside those of version 6: the trial and
      // bracket limits, TPE's effective start-up and constants, the space (results/search_store.cpp).
      search_store_sql::kSettingsMigration,
      // 8: TPE's estimator rule, joint or per axis (NULL: per axis, as every TPE search before it).
      search_store_sql::kTpeRuleMigration,
      // 9: the joint rule's constants w, h, λ (NULL: the version-8 build's, 1, 0.2 and 0.7).
      search_store_sql::kTpeConstantsMigration,
  };
  return scripts;
}

// Applies the migrations after `version` in one transaction. The generated per-sweep views are
// dropped first (they name columns of the old tables) and written anew afterwards; the fixed
// views stay (a migration that changes one's tables drops and recreates it itself).
void migrate(SqliteConnection& db, std::int64_t version) {
  SqliteTransaction transaction(db);
  // Read again under the write lock: another process may have created or migrated the file
  // since `version` was read (two runs starting on one fresh file).
  version = db.query_int("PRAGMA user_version");
  if (version > kResultsSchemaVersion) {
    throw StoreError(db.path() + ": written by a newer armfarm (schema version " + std::to_string(version) + ")");
  }
  if (version == kResultsSchemaVersion) {
    transaction.commit();
    return;
  }
  if (version >= 1) {
    std::vector<std::string> views;
    SqliteStatement statement = db.prepare(
        "SELECT name FROM sqlite_master WHERE type = 'view' AND name NOT IN ('job_metrics', 'sweep_job_status', "
        "'search_promotions')");
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

namespace {

// One table's columns as SQLite reports them: "name type notnull pk" per column.
using TableShape = std::vector<std::string>;

std::map<std::string, TableShape> read_table_shapes(SqliteConnection& db) {
  std::map<std::string, TableShape> tables;
  SqliteStatement names =
      db.prepare("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' ORDER BY name");
  while (names.step()) tables[names.column_text(0)];
  for (auto& [table, shape] : tables) {
    SqliteStatement columns = db.prepare("SELECT name, upper(type), \"notnull\", pk FROM pragma_table_info(?)");
    columns.bind(1, table);
    while (columns.step()) {
      shape.push_back(columns.column_text(0) + " " + columns.column_text(1) + " " +
                      std::to_string(columns.column_int(2)) + " " + std::to_string(columns.column_int(3)));
    }
  }
  return tables;
}

std::set<std::string> read_object_names(SqliteConnection& db, const char* type) {
  std::set<std::string> names;
  SqliteStatement statement =
      db.prepare("SELECT name FROM sqlite_master WHERE type = ? AND name NOT LIKE 'sqlite_%'");
  statement.bind(1, type);
  while (statement.step()) names.insert(statement.column_text(0));
  return names;
}

}  // namespace

// The structure a file of `version` must have is the one its migrations build: they are run on
// an empty in-memory database and the two compared, table by table and column by column (name,
// declared type, NOT NULL, primary key), with every index and fixed view present. Extra tables,
// indexes and views (a user's own, the per-sweep views) are allowed.
void verify_structure(SqliteConnection& db, std::int64_t version) {
  SqliteConnection expected(db.path(), std::string(":memory:"));
  for (std::int64_t k = 0; k < version; ++k) expected.execute(migrations()[static_cast<std::size_t>(k)]);
  const std::string where = db.path() + ": damaged armfarm database (schema version " + std::to_string(version) + "): ";
  const std::map<std::string, TableShape> want = read_table_shapes(expected), have = read_table_shapes(db);
  for (const auto& [table, columns] : want) {
    const auto found = have.find(table);
    if (found == have.end()) throw StoreError(where + "table " + table + " is missing");
    for (const std::string& column : columns) {
      if (std::find(found->second.begin(), found->second.end(), column) == found->second.end()) {
        const std::string name = column.substr(0, column.find(' '));
        throw StoreError(where + "column " + table + "." + name + " is missing or has another type");
      }
    }
  }
  for (const char* type : {"index", "view"}) {
    const std::set<std::string> present = read_object_names(db, type);
    for (const std::string& name : read_object_names(expected, type)) {
      if (!present.count(name)) throw StoreError(where + type + " " + name + " is missing");
    }
  }
}

namespace {

// True when SQLite refused because another connection holds the file (SQLITE_BUSY, "database is
// locked", or SQLITE_LOCKED, "database table is locked"; any of their extended codes).
bool is_lock_conflict(const StoreError& error) {
  const int primary = error.sqlite_code() & 0xff;
  return primary == SQLITE_BUSY || primary == SQLITE_LOCKED;
}

}  // namespace

// Opens the file and checks it is an armfarm database this build can read; migrates when writable.
std::unique_ptr<SqliteConnection> open_checked(const std::string& path, ResultsStore::Mode mode) {
  const bool read_only = mode == ResultsStore::Mode::read_only;
  if (read_only && !std::filesystem::exists(path)) throw StoreError(path + ": no such database file");
  if (std::filesystem::is_directory(path)) throw StoreError(path + ": is a directory, not a database file");
  // A FIFO, a device or a socket would block or be read as garbage: refused before SQLite opens it.
  const std::filesystem::file_status status = std::filesystem::status(path);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    throw StoreError(path + ": not a regular file (a FIFO, device or socket), not a database file");
  }
  auto db = std::make_unique<SqliteConnection>(path, read_only);

  std::int64_t application_id = 0, version = 0, n_tables = 0;
  try {
    // One read transaction: the three from one snapshot, even while another process creates
    // the schema of a fresh file.
    db->execute("BEGIN");
    application_id = db->query_int("PRAGMA application_id");
    version = db->query_int("PRAGMA user_version");
    n_tables = db->query_int("SELECT count(*) FROM sqlite_master");
    db->execute("COMMIT");
  } catch (const StoreError& e) {
    throw StoreError(path + ": not a readable SQLite database (" + e.detail() + ")");
  }
  const bool fresh = application_id == 0 && version == 0 && n_tables == 0;
  if (!fresh && application_id != kApplicationId) {
    throw StoreError(path + ": an SQLite database, but not an armfarm results database");
  }
  if (version > kResultsSchemaVersion) {
    throw StoreError(path + ": written by a newer armfarm (schema version " + std::to_string(version) +
                     "; this build reads up to version " + std::to_string(kResultsSchemaVersion) + ")");
  }
  if (!fresh) verify_structure(*db, version);
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

  // Switching a fresh file to WAL needs it to itself for a moment, and SQLite does not wait for
  // that: another process opening the same fresh file at once gets "database is locked". Retry
  // for up to the busy timeout (10 s).
  for (int attempt = 0;; ++attempt) {
    try {
      db->execute("PRAGMA journal_mode = WAL");
      break;
    } catch (const StoreError& e) {
      if (attempt >= 1000 || !is_lock_conflict(e)) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  db->execute("PRAGMA synchronous = NORMAL");
  db->execute("PRAGMA foreign_keys = ON");
  if (version < kResultsSchemaVersion) migrate(*db, version);
  return db;
}

}  // namespace store_detail
}  // namespace armfarm
