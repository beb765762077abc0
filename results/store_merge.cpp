// Merging another results file into this one, job by job, without losing a finished result.
#include "results/search_store.hpp"
#include "results/series_codec.hpp"
#include "results/store_internal.hpp"

#include <filesystem>
#include <map>
#include <set>
#include <unistd.h>

namespace armfarm {

using namespace store_detail;

void ResultsStore::copy_to(const std::string& path) const { db_->copy_to_file(path); }

namespace {

using IdMap = std::map<std::int64_t, std::int64_t>;  // src id -> main id

/// A migrated copy of the other file, removed (with its -wal and -shm) when it goes.
struct TemporaryCopy {
  std::string path;
  ~TemporaryCopy() {
    if (path.empty()) return;
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix, ignored);
  }
};

/// The file to attach: the other file itself, or when its schema is older a migrated temporary
/// copy of it in `copy` (the other file is only read).
std::string prepare_attached_file(const std::string& other_path, TemporaryCopy& copy) {
  const std::int64_t other_version = SqliteConnection(other_path, true).query_int("PRAGMA user_version");
  if (other_version >= kResultsSchemaVersion) return other_path;
  std::string pattern = (std::filesystem::temp_directory_path() / "armfarm-merge-XXXXXX").string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0) throw StoreError(other_path + ": cannot create a temporary copy to migrate");
  close(fd);
  std::filesystem::remove(pattern);
  copy.path = pattern;
  SqliteConnection(other_path, true).copy_to_file(copy.path);
  { ResultsStore migrated = ResultsStore::open(copy.path, ResultsStore::Mode::read_write); }
  return copy.path;
}

/// Detaches `src` however the merge ends.
struct Detach {
  SqliteConnection& db;
  ~Detach() {
    try {
      db.execute("DETACH DATABASE src");
    } catch (const StoreError&) {
    }
  }
};

/// Sweeps: new ones are copied; a sweep of the same name must have the same spec. Their runs
/// come along (each once). Returns the sweep ids; adds the sweeps' names to `touched`.
IdMap merge_sweeps(SqliteConnection& db, const std::string& other_path, MergeReport& report,
                   std::set<std::string>& touched) {
  IdMap sweep_id_map;
  SqliteStatement src_sweeps = db.prepare(std::string("SELECT ") + kSweepColumns + " FROM src.sweeps ORDER BY id");
  while (src_sweeps.step()) {
    const SweepRecord sweep = read_sweep_row(src_sweeps);
    touched.insert(sweep.name);
    SqliteStatement mine = db.prepare("SELECT id, spec_hash FROM main.sweeps WHERE name = ?");
    mine.bind(1, sweep.name);
    if (mine.step()) {
      sweep_id_map[sweep.id] = mine.column_int(0);
      if (mine.column_text(1) != sweep.spec_hash) {
        report.conflicts.push_back("sweep " + sweep.name + ": different specs (hash " + mine.column_text(1) +
                                   " here, " + sweep.spec_hash + " in " + other_path + ")");
      }
      db.prepare("UPDATE main.sweeps SET started_at = min(started_at, ?) WHERE id = ?")
          .bind(1, sweep.started_at)
          .bind(2, sweep_id_map[sweep.id])
          .execute();
    } else {
      db.prepare(std::string("INSERT INTO main.sweeps (") + kSweepColumns + ") SELECT NULL, " +
                 std::string(kSweepColumns).substr(4) + " FROM src.sweeps WHERE id = ?")
          .bind(1, sweep.id)
          .execute();
      sweep_id_map[sweep.id] = db.last_insert_rowid();
    }
    db.prepare(
          "INSERT INTO main.runs (sweep_id, started_at, finished_at, status, shard, jobs_total, jobs_skipped, "
          "jobs_run, armfarm_version, git_commit, host) SELECT ?1, started_at, finished_at, status, shard, "
          "jobs_total, jobs_skipped, jobs_run, armfarm_version, git_commit, host FROM src.runs s WHERE sweep_id = ?2 "
          "AND NOT EXISTS (SELECT 1 FROM main.runs r WHERE r.sweep_id = ?1 AND r.started_at = s.started_at AND "
          "r.shard IS s.shard AND r.host IS s.host)")
        .bind(1, sweep_id_map[sweep.id])
        .bind(2, sweep.id)
        .execute();
  }
  return sweep_id_map;
}

/// What the metrics mean: the other file's entries for names this file does not know. Returns
/// the names of the timing and diagnostic metrics: they vary from run to run, never a conflict.
std::set<std::string> merge_metric_info(SqliteConnection& db) {
  db.execute("INSERT INTO main.metric_info SELECT * FROM src.metric_info WHERE true ON CONFLICT(name) DO NOTHING");
  std::set<std::string> not_results;
  SqliteStatement statement = db.prepare(
      "SELECT name FROM main.metric_info WHERE kind != 'result' UNION SELECT name FROM src.metric_info "
      "WHERE kind != 'result'");
  while (statement.step()) not_results.insert(statement.column_text(0));
  return not_results;
}

/// The two sides of a merge, for comparing one job's results: `main` is this file, `src` the other.
struct MergeSides {
  SqliteConnection& db;
  const std::string& main_path;
  const std::string& other_path;
  const std::set<std::string>& not_results;

  const std::string& file_of(const std::string& schema) const { return schema == "src" ? other_path : main_path; }
};

/// A job's result metrics (not its timing and diagnostic ones), in a stable order.
std::vector<MetricRecord> find_result_metrics(const MergeSides& sides, const std::string& schema, std::int64_t job_id) {
  SqliteStatement statement = sides.db.prepare("SELECT job_id, name, joint, checkpoint, value, reason FROM " + schema +
                                               ".metrics WHERE job_id = ? ORDER BY name, joint, checkpoint");
  statement.bind(1, job_id);
  std::vector<MetricRecord> results;
  for (MetricRecord& metric : read_metrics(statement)) {
    if (!sides.not_results.count(metric.name)) results.push_back(std::move(metric));
  }
  return results;
}

/// A job's series: name, column names, encoding and the decoded bytes (compared bit for bit, NaN included).
std::vector<std::string> find_series_texts(const MergeSides& sides, const std::string& schema, std::int64_t job_id) {
  SqliteStatement statement = sides.db.prepare("SELECT name, columns, rows, dtype, layout, data FROM " + schema +
                                               ".series WHERE job_id = ? ORDER BY name");
  statement.bind(1, job_id);
  std::vector<std::string> all;
  while (statement.step()) {
    const std::string& file = sides.file_of(schema);
    const auto n_columns = static_cast<long>(parse_stored_json(statement.column_text(1), file).size());
    const Eigen::MatrixXd rows =
        calc_series_matrix(statement.column_blob(5), static_cast<long>(statement.column_int(2)), n_columns, file);
    all.push_back(statement.column_text(0) + "\n" + statement.column_text(1) + "\n" + statement.column_text(3) +
                  statement.column_text(4) + "\n" +
                  std::string(reinterpret_cast<const char*>(rows.data()), rows.size() * sizeof(double)));
  }
  return all;
}

std::string find_model_hash(const MergeSides& sides, const std::string& schema, std::int64_t job_id) {
  SqliteStatement statement = sides.db.prepare("SELECT hash FROM " + schema + ".models WHERE job_id = ?");
  statement.bind(1, job_id);
  return statement.step() ? statement.column_text(0) : std::string();
}

/// Whether a job present on both sides computed the same: status, result metrics, series, model.
bool has_same_results(const MergeSides& sides, std::int64_t main_id, const std::string& main_status,
                      std::int64_t src_id, const std::string& src_status) {
  const auto main_metrics = find_result_metrics(sides, "main", main_id);
  const auto src_metrics = find_result_metrics(sides, "src", src_id);
  bool same = main_status == src_status && main_metrics.size() == src_metrics.size();
  for (std::size_t i = 0; same && i < main_metrics.size(); ++i) {
    const MetricRecord &a = main_metrics[i], &b = src_metrics[i];
    same = a.name == b.name && a.joint == b.joint && a.checkpoint == b.checkpoint && a.value == b.value &&
           a.reason == b.reason;
  }
  if (same) same = find_series_texts(sides, "main", main_id) == find_series_texts(sides, "src", src_id);
  if (same) same = find_model_hash(sides, "main", main_id) == find_model_hash(sides, "src", src_id);
  return same;
}

/// Replaces the results (metrics, series, model) of main's job `main_id` by src's job `src_id`'s.
void copy_results(SqliteConnection& db, std::int64_t src_id, std::int64_t main_id) {
  db.prepare("DELETE FROM main.metrics WHERE job_id = ?").bind(1, main_id).execute();
  db.prepare("DELETE FROM main.series WHERE job_id = ?").bind(1, main_id).execute();
  db.prepare("DELETE FROM main.models WHERE job_id = ?").bind(1, main_id).execute();
  db.prepare("INSERT INTO main.models (job_id, kind, hash, bytes, data) SELECT ?, kind, hash, bytes, data "
             "FROM src.models WHERE job_id = ?")
      .bind(1, main_id)
      .bind(2, src_id)
      .execute();
  db.prepare("INSERT INTO main.metrics (job_id, name, joint, checkpoint, value, reason) "
             "SELECT ?, name, joint, checkpoint, value, reason FROM src.metrics WHERE job_id = ?")
      .bind(1, main_id)
      .bind(2, src_id)
      .execute();
  db.prepare("INSERT INTO main.series (job_id, name, columns, rows, dtype, layout, codec, raw_bytes, data) "
             "SELECT ?, name, columns, rows, dtype, layout, codec, raw_bytes, data FROM src.series WHERE job_id = ?")
      .bind(1, main_id)
      .bind(2, src_id)
      .execute();
}

constexpr const char* kCopiedColumns =
    "sweep, params, config, status, message, seed, end_time, wall_seconds, started_at, finished_at, attempts";

/// One job of the other file: added when new here, replaced when only the other finished it,
/// kept when only this file did, otherwise compared (identical or a conflict; this file's kept).
/// Returns its id here.
std::int64_t merge_job(const MergeSides& sides, std::int64_t src_id, const std::string& key,
                       const std::string& src_status, MergeReport& report) {
  SqliteConnection& db = sides.db;
  SqliteStatement mine = db.prepare("SELECT id, status FROM main.jobs WHERE key = ?");
  mine.bind(1, key);
  if (!mine.step()) {
    db.prepare(std::string("INSERT INTO main.jobs (key, ") + kCopiedColumns + ") SELECT key, " + kCopiedColumns +
               " FROM src.jobs WHERE id = ?")
        .bind(1, src_id)
        .execute();
    const std::int64_t main_id = db.last_insert_rowid();
    copy_results(db, src_id, main_id);
    ++report.jobs_added;
    return main_id;
  }
  const std::int64_t main_id = mine.column_int(0);
  const std::string main_status = mine.column_text(1);
  if (src_status != "done" && main_status == "done") {
    ++report.jobs_identical;  // nothing new in the other file: keep the finished job
    return main_id;
  }
  if (src_status == "done" && main_status != "done") {
    db.prepare(std::string("UPDATE main.jobs SET (") + kCopiedColumns + ") = (SELECT " + kCopiedColumns +
               " FROM src.jobs WHERE id = ?) WHERE id = ?")
        .bind(1, src_id)
        .bind(2, main_id)
        .execute();
    copy_results(db, src_id, main_id);
    ++report.jobs_replaced;
    return main_id;
  }
  if (has_same_results(sides, main_id, main_status, src_id, src_status)) {
    ++report.jobs_identical;
  } else {
    report.conflicts.push_back("job " + key + ": different results (" + main_status + " here, " + src_status +
                               " in " + sides.other_path + "); kept this file's");
  }
  return main_id;
}

/// Jobs, compared by key. Returns the job ids.
IdMap merge_jobs(const MergeSides& sides, MergeReport& report) {
  IdMap job_id_map;
  SqliteStatement src_jobs = sides.db.prepare("SELECT id, key, status FROM src.jobs ORDER BY id");
  while (src_jobs.step()) {
    const std::int64_t src_id = src_jobs.column_int(0);
    job_id_map[src_id] = merge_job(sides, src_id, src_jobs.column_text(1), src_jobs.column_text(2), report);
  }
  return job_id_map;
}

/// Which jobs belong to which sweeps, ids mapped.
void merge_memberships(SqliteConnection& db, const IdMap& sweep_id_map, const IdMap& job_id_map) {
  SqliteStatement members = db.prepare("SELECT sweep_id, job_id, position, params FROM src.sweep_jobs");
  SqliteStatement insert_member = db.prepare(
      "INSERT INTO main.sweep_jobs (sweep_id, job_id, position, params) VALUES (?, ?, ?, ?) "
      "ON CONFLICT(sweep_id, job_id) DO NOTHING");
  while (members.step()) {
    insert_member.bind(1, sweep_id_map.at(members.column_int(0)))
        .bind(2, job_id_map.at(members.column_int(1)))
        .bind(3, members.column_int(2))
        .bind(4, members.column_text(3))
        .execute();
  }
}

}  // namespace

MergeReport ResultsStore::merge_from(const std::string& other_path) {
  // Checks the other file is an armfarm database this build reads before touching anything.
  verify_file(other_path);
  TemporaryCopy copy;
  const std::string attached_path = prepare_attached_file(other_path, copy);
  MergeReport report;
  db_->prepare("ATTACH DATABASE ? AS src").bind(1, attached_path).execute();
  const Detach detach{*db_};

  std::set<std::string> touched_sweeps;
  {
    SqliteTransaction transaction(*db_);
    const IdMap sweep_id_map = merge_sweeps(*db_, other_path, report, touched_sweeps);
    const std::set<std::string> not_results = merge_metric_info(*db_);
    const IdMap job_id_map = merge_jobs(MergeSides{*db_, path_, other_path, not_results}, report);
    merge_memberships(*db_, sweep_id_map, job_id_map);
    // Searches (results/search_store.hpp): their rungs, trials and steps, jobs mapped.
    merge_search_tables(*db_, sweep_id_map, job_id_map, other_path, report);
    transaction.commit();
  }
  for (const std::string& sweep : touched_sweeps) update_sweep_view(sweep);
  return report;
}

}  // namespace armfarm