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

MergeReport ResultsStore::merge_from(const std::string& other_path) {
  // Checks the other file is an armfarm database this build reads before touching anything;
  // an older schema is merged from a migrated temporary copy (the file itself is only read).
  verify_file(other_path);
  std::int64_t other_version = 0;
  {
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
             "jobs_run, armfarm_version, git_commit, host) SELECT ?1, started_at, finished_at, status, shard, "
             "jobs_total, jobs_skipped, jobs_run, armfarm_version, git_commit, host FROM src.runs s WHERE sweep_id = ?2 "
             "AND NOT EXISTS (SELECT 1 FROM main.runs r WHERE r.sweep_id = ?1 AND r.started_at = s.started_at AND "
             "r.shard IS s.shard AND r.host IS s.host)")
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
        const std::string& file = schema == "src" ? other_path : path_;
        const auto n_columns = static_cast<long>(parse_stored_json(statement.column_text(1), file).size());
        const Eigen::MatrixXd rows =
            calc_series_matrix(statement.column_blob(5), static_cast<long>(statement.column_int(2)), n_columns,
                               file);
        all.push_back(statement.column_text(0) + "\n" + statement.column_text(1) + "\n" + statement.column_text(3) +
                      statement.column_text(4) + "\n" +
                      std::string(reinterpret_cast<const char*>(rows.data()), rows.size() * sizeof(double)));
      }
      return all;
    };
    auto copy_results = [&](std::int64_t src_id, std::int64_t main_id) {
      db_->prepare("DELETE FROM main.metrics WHERE job_id = ?").bind(1, main_id).execute();
      db_->prepare("DELETE FROM main.series WHERE job_id = ?").bind(1, main_id).execute();
      db_->prepare("DELETE FROM main.models WHERE job_id = ?").bind(1, main_id).execute();
      db_->prepare("INSERT INTO main.models (job_id, kind, hash, bytes, data) SELECT ?, kind, hash, bytes, data "
                   "FROM src.models WHERE job_id = ?")
          .bind(1, main_id)
          .bind(2, src_id)
          .execute();
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
        const auto model_hash_of = [&](const std::string& schema, std::int64_t job_id) {
          SqliteStatement statement = db_->prepare("SELECT hash FROM " + schema + ".models WHERE job_id = ?");
          statement.bind(1, job_id);
          return statement.step() ? statement.column_text(0) : std::string();
        };
        same = model_hash_of("main", main_id) == model_hash_of("src", src_id);
      }
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
    // Searches (results/search_store.hpp): their rungs, trials and steps, jobs mapped.
    merge_search_tables(*db_, sweep_id_map, job_id_map, other_path, report);
    transaction.commit();
  }
  for (const std::string& sweep : touched_sweeps) update_sweep_view(sweep);
  return report;
}

}  // namespace armfarm