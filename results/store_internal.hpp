#pragma once
// Internal to results/: the helpers the store's files share (schema, row readers, SQL quoting).
// Not a public header: nothing outside results/ includes it.
#include "results/results_store.hpp"
#include "results/sqlite_connection.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armfarm {
namespace store_detail {

inline constexpr std::int64_t kApplicationId = 0x41524D46;  // "ARMF"

// ---- schema (store_schema.cpp) ----
/// Migration k (1-based) moves the schema from version k-1 to k.
const std::vector<const char*>& migrations();
/// Applies the migrations after `version` in one transaction and rewrites the sweep views.
void migrate(SqliteConnection& db, std::int64_t version);
/// Throws StoreError naming the file when a table, column (name and declared type), index or
/// fixed view of schema `version` is missing.
void verify_structure(SqliteConnection& db, std::int64_t version);
/// Opens `path`, checks it is an armfarm database this build reads, migrates it when writable.
std::unique_ptr<SqliteConnection> open_checked(const std::string& path, ResultsStore::Mode mode);

// ---- rows and quoting (store_rows.cpp) ----
std::string quote_identifier(const std::string& name);
std::string quote_literal(const std::string& text);
/// Parses JSON text stored in a column; throws StoreError naming `where`.
nlohmann::json parse_stored_json(const std::string& text, const std::string& where);
std::vector<std::string> find_sweep_names(SqliteConnection& db);
/// Column lists the row readers expect, in order.
inline constexpr const char* kJobColumns =
    "j.id, j.key, j.sweep, j.params, j.config, j.status, j.message, j.seed, j.end_time, j.wall_seconds, "
    "j.started_at, j.finished_at, j.attempts";
inline constexpr const char* kSweepColumns =
    "id, name, description, spec_text, spec_hash, started_at, finished_at, armfarm_version, git_commit, git_dirty, "
    "compiler, simbody_version, host";
JobRecord read_job_row(const SqliteStatement& row, const std::string& where);
SweepRecord read_sweep_row(const SqliteStatement& row);
/// Reads rows of (job_id, name, joint, checkpoint, value, reason).
std::vector<MetricRecord> read_metrics(SqliteStatement& statement);

// ---- writes (store_writes.cpp) ----
void upsert_metric_info_rows(SqliteConnection& db, const std::vector<MetricInfoRecord>& records);
void insert_metrics_and_series(SqliteConnection& db, std::int64_t job_id, const JobResultRecord& result);

// ---- sweep views (sweep_views.cpp) ----
/// Drops and writes the view of one sweep (its parameters and metrics as columns).
void write_sweep_view(SqliteConnection& db, const std::string& sweep);

}  // namespace store_detail
}  // namespace armfarm
