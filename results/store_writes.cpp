// Writes: registering a sweep run, committing finished jobs, closing a run.
#include "results/model_store.hpp"
#include "results/series_codec.hpp"
#include "results/store_internal.hpp"

#include "results/job_claims.hpp"

#include <cmath>

namespace armfarm {
namespace store_detail {

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

}  // namespace store_detail
}  // namespace armfarm

namespace armfarm {

using namespace store_detail;

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

std::vector<std::string> ResultsStore::insert_job_batch(const JobBatch& batch, const std::string& sweep_name) {
  SqliteTransaction transaction(*db_);
  std::vector<std::string> discarded;
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
    // The fence: a result whose claim was taken over (this runner was paused or cut off past the
    // lease) is not written, whatever it says; the job belongs to the claim's new holder.
    if (!batch.claim_owner.empty() &&
        !job_claims_sql::is_claim_current(*db_, result.key, batch.claim_owner, result.claim_generation)) {
      discarded.push_back(result.key);
      continue;
    }
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
    if (!batch.claim_owner.empty()) job_claims_sql::release_claim(*db_, job_id, batch.claim_owner);
    replace_job_model(*db_, job_id, result.model);
  }
  if (!batch.abandoned.empty()) {
    SqliteStatement abandoned =
        db_->prepare("UPDATE jobs SET status = 'pending' WHERE key = ? AND status = 'running'");
    for (const std::string& key : batch.abandoned) {
      // A claimed job goes back to pending only while its claim is still this owner's (a claim
      // taken over belongs to the runner now running the job).
      if (!batch.claim_owner.empty()) {
        SqliteStatement id = db_->prepare("SELECT id FROM jobs WHERE key = ?");
        id.bind(1, key);
        if (!id.step() || !job_claims_sql::release_claim(*db_, id.column_int(0), batch.claim_owner)) continue;
      }
      abandoned.bind(1, key).execute();
    }
  }
  transaction.commit();
  return discarded;
}

void ResultsStore::update_run_finished(std::int64_t run_id, const std::string& status, int jobs_run, int jobs_skipped,
                                       const std::string& finished_at) {
  std::string sweep_name;
  {
    SqliteTransaction transaction(*db_);
    // A row another runner marked `interrupted` (this process went without a heartbeat past the
    // lease: paused or cut off, its claims taken over) stays so: the run did not hold its jobs
    // to the end, whatever it finished afterwards.
    SqliteStatement current = db_->prepare("SELECT status FROM runs WHERE id = ?");
    current.bind(1, run_id);
    if (!current.step()) throw StoreError(path_ + ": no run " + std::to_string(run_id));
    const std::string final_status = current.column_text(0) == "interrupted" ? "interrupted" : status;
    db_->prepare("UPDATE runs SET status = ?, jobs_run = ?, jobs_skipped = ?, finished_at = ? WHERE id = ?")
        .bind(1, final_status)
        .bind(2, jobs_run)
        .bind(3, jobs_skipped)
        .bind(4, finished_at)
        .bind(5, run_id)
        .execute();
    if (final_status == "complete") {
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

void ResultsStore::upsert_metric_info(const std::vector<MetricInfoRecord>& records) {
  SqliteTransaction transaction(*db_);
  upsert_metric_info_rows(*db_, records);
  transaction.commit();
}

}  // namespace armfarm
