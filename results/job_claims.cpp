// Job claims in the store (results/job_claims.hpp): the claim, heartbeat, stale-claim and
// listing queries of ResultsStore, and the migration step that adds `job_claims`.
#include "results/job_claims.hpp"

#include "results/results_store.hpp"
#include "results/sqlite_connection.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace armfarm {

namespace job_claims_sql {

const char* const kMigration = R"sql(
CREATE TABLE job_claims (
  id INTEGER PRIMARY KEY,
  job_id INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
  run_id INTEGER REFERENCES runs(id) ON DELETE SET NULL,
  owner TEXT NOT NULL,
  host TEXT NOT NULL,
  pid INTEGER NOT NULL,
  claimed_at TEXT NOT NULL,
  heartbeat_at TEXT NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('live', 'interrupted')),
  interrupted_at TEXT,
  interrupted_by TEXT
);
CREATE UNIQUE INDEX job_claims_live_by_job ON job_claims(job_id) WHERE state = 'live';
CREATE INDEX job_claims_live_by_owner ON job_claims(owner) WHERE state = 'live';
ALTER TABLE runs ADD COLUMN owner TEXT;
ALTER TABLE runs ADD COLUMN pid INTEGER;
ALTER TABLE runs ADD COLUMN heartbeat_at TEXT;
)sql";

bool release_claim(SqliteConnection& db, std::int64_t job_id, const std::string& owner) {
  db.prepare("DELETE FROM job_claims WHERE job_id = ? AND owner = ? AND state = 'live'")
      .bind(1, job_id)
      .bind(2, owner)
      .execute();
  return db.changes() > 0;
}

const char* const kFencingMigration = R"sql(
CREATE TABLE claim_lease (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  seconds REAL NOT NULL CHECK (typeof(seconds) = 'real' AND seconds > 0),
  changed_at TEXT
);
INSERT INTO claim_lease (id, seconds) VALUES (1, 60.0);
ALTER TABLE jobs ADD COLUMN claim_generation INTEGER NOT NULL DEFAULT 0;
ALTER TABLE job_claims ADD COLUMN generation INTEGER NOT NULL DEFAULT 0;
)sql";

bool is_claim_current(SqliteConnection& db, const std::string& key, const std::string& owner,
                      std::int64_t generation) {
  SqliteStatement current = db.prepare(
      "SELECT 1 FROM jobs j JOIN job_claims c ON c.job_id = j.id AND c.state = 'live' "
      "WHERE j.key = ? AND c.owner = ? AND c.generation = ? AND j.claim_generation = c.generation");
  current.bind(1, key).bind(2, owner).bind(3, generation);
  return current.step();
}

double read_lease_seconds(SqliteConnection& db) {
  SqliteStatement lease = db.prepare("SELECT seconds FROM claim_lease WHERE id = 1");
  if (!lease.step()) throw StoreError(db.path() + ": damaged armfarm database: table claim_lease has no row");
  return lease.column_double(0);
}

}  // namespace job_claims_sql

namespace {

// Seconds between two ISO-8601 UTC times, in SQL (julianday reads our "...T12:34:56.789Z").
constexpr const char* kAgeOfHeartbeat = "((julianday(?1) - julianday(heartbeat_at)) * 86400.0)";

// Marks one stale live claim interrupted, its run interrupted and (unless `keep_running`) its job pending.
void interrupt_claim(SqliteConnection& db, std::int64_t claim_id, std::int64_t job_id,
                     const std::optional<std::int64_t>& run_id, const std::string& now, const std::string& by,
                     bool keep_running) {
  db.prepare("UPDATE job_claims SET state = 'interrupted', interrupted_at = ?, interrupted_by = ? WHERE id = ?")
      .bind(1, now)
      .bind(2, by)
      .bind(3, claim_id)
      .execute();
  if (!keep_running) {
    db.prepare("UPDATE jobs SET status = 'pending' WHERE id = ? AND status = 'running'").bind(1, job_id).execute();
  }
  if (run_id) {
    db.prepare("UPDATE runs SET status = 'interrupted' WHERE id = ? AND status = 'running'").bind(1, *run_id).execute();
  }
}

}  // namespace

std::string make_claim_owner_id(const std::string& host, std::int64_t pid) {
  const auto nanoseconds =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "%llx", static_cast<unsigned long long>(nanoseconds));
  return host + ":" + std::to_string(pid) + ":" + suffix;
}

ClaimAttempt ResultsStore::claim_job(const std::string& key, const ClaimOwner& owner, const std::string& now,
                                     const std::optional<std::string>& redo_done_before) {
  SqliteTransaction transaction(*db_);
  const double timeout_seconds = job_claims_sql::read_lease_seconds(*db_);
  SqliteStatement job = db_->prepare(std::string("SELECT j.id, j.status, j.finished_at, c.id, c.owner, c.run_id, ") +
                                     kAgeOfHeartbeat +
                                     ", j.claim_generation FROM jobs j LEFT JOIN job_claims c ON c.job_id = j.id AND c.state = 'live' "
                                     "WHERE j.key = ?2");
  job.bind(1, now).bind(2, key);
  if (!job.step()) throw StoreError(path_ + ": job " + key + " is not registered");
  const std::int64_t job_id = job.column_int(0);
  const std::string status = job.column_text(1);
  const std::optional<std::string> finished_at = job.column_optional_text(2);
  ClaimAttempt attempt;
  if (!job.is_null(3)) {
    const std::string holder = job.column_text(4);
    if (holder == owner.owner) {  // already ours
      attempt.generation = job.column_int(7);
      return attempt;
    }
    if (!(job.column_double(6) > timeout_seconds)) {
      attempt.result = ClaimResult::claimed_elsewhere;
      attempt.other_owner = holder;
      return attempt;
    }
    const std::optional<std::int64_t> run_id =
        job.is_null(5) ? std::nullopt : std::optional<std::int64_t>(job.column_int(5));
    interrupt_claim(*db_, job.column_int(3), job_id, run_id, now, owner.owner, false);
    attempt.taken_over = holder;
  }
  if (status == "done" && !(redo_done_before && finished_at && *finished_at < *redo_done_before)) {
    transaction.commit();  // keeps the interrupted mark, if any
    attempt.result = ClaimResult::done;
    return attempt;
  }
  // The fencing token: one more than any claim of this job ever had.
  attempt.generation = job.column_int(7) + 1;
  db_->prepare(
         "INSERT INTO job_claims (job_id, run_id, owner, host, pid, claimed_at, heartbeat_at, state, generation) "
         "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?6, 'live', ?7)")
      .bind(1, job_id)
      .bind(2, owner.run_id)
      .bind(3, owner.owner)
      .bind(4, owner.host)
      .bind(5, owner.pid)
      .bind(6, now)
      .bind(7, attempt.generation)
      .execute();
  db_->prepare(
         "UPDATE jobs SET status = 'running', attempts = attempts + 1, sweep = ?, started_at = ?, finished_at = NULL, "
         "claim_generation = ? WHERE id = ?")
      .bind(1, owner.sweep)
      .bind(2, now)
      .bind(3, attempt.generation)
      .bind(4, job_id)
      .execute();
  transaction.commit();
  attempt.result = ClaimResult::claimed;
  return attempt;
}

std::vector<std::string> ResultsStore::refresh_claims(const ClaimOwner& owner, const std::string& now) {
  SqliteTransaction transaction(*db_);
  db_->prepare("UPDATE runs SET owner = ?, pid = ?, heartbeat_at = ? WHERE id = ?")
      .bind(1, owner.owner)
      .bind(2, owner.pid)
      .bind(3, now)
      .bind(4, owner.run_id)
      .execute();
  db_->prepare("UPDATE job_claims SET heartbeat_at = ? WHERE owner = ? AND state = 'live'")
      .bind(1, now)
      .bind(2, owner.owner)
      .execute();
  SqliteStatement held = db_->prepare(
      "SELECT j.key FROM job_claims c JOIN jobs j ON j.id = c.job_id WHERE c.owner = ? AND c.state = 'live' "
      "ORDER BY j.key");
  held.bind(1, owner.owner);
  std::vector<std::string> keys;
  while (held.step()) keys.push_back(held.column_text(0));
  transaction.commit();
  return keys;
}

StaleClaimReport ResultsStore::interrupt_stale_claims(const std::string& now, const std::string& by_owner,
                                                      const std::vector<std::string>& dead_owners) {
  SqliteTransaction transaction(*db_);
  const double timeout_seconds = job_claims_sql::read_lease_seconds(*db_);
  StaleClaimReport report;
  struct Stale {
    std::int64_t claim_id, job_id;
    std::optional<std::int64_t> run_id;
  };
  std::vector<Stale> stale;
  {
    SqliteStatement find = db_->prepare(std::string("SELECT id, job_id, run_id FROM job_claims WHERE state = 'live' AND ") +
                                        kAgeOfHeartbeat + " > ?2 ORDER BY id");
    find.bind(1, now).bind(2, timeout_seconds);
    while (find.step()) {
      stale.push_back({find.column_int(0), find.column_int(1),
                       find.is_null(2) ? std::nullopt : std::optional<std::int64_t>(find.column_int(2))});
    }
    // The dead owners' claims that are not stale already (those are in the list above).
    SqliteStatement dead = db_->prepare(std::string("SELECT id, job_id, run_id FROM job_claims WHERE state = 'live' AND ") +
                                        kAgeOfHeartbeat + " <= ?2 AND owner = ?3 ORDER BY id");
    for (const std::string& owner : dead_owners) {
      dead.reset();
      dead.bind(1, now).bind(2, timeout_seconds).bind(3, owner);
      while (dead.step()) {
        stale.push_back({dead.column_int(0), dead.column_int(1),
                         dead.is_null(2) ? std::nullopt : std::optional<std::int64_t>(dead.column_int(2))});
      }
    }
  }
  for (const Stale& s : stale) interrupt_claim(*db_, s.claim_id, s.job_id, s.run_id, now, by_owner, false);
  report.claims_interrupted = static_cast<int>(stale.size());
  // Jobs left `running` with no live claim (killed under a build before claims) go back to pending.
  db_->execute(
      "UPDATE jobs SET status = 'pending' WHERE status = 'running' AND NOT EXISTS "
      "(SELECT 1 FROM job_claims c WHERE c.job_id = jobs.id AND c.state = 'live')");
  // Runs whose process stopped refreshing its heartbeat (or never had one and started long ago).
  db_->prepare(
         "UPDATE runs SET status = 'interrupted' WHERE status = 'running' AND "
         "(julianday(?1) - julianday(coalesce(heartbeat_at, started_at))) * 86400.0 > ?2")
      .bind(1, now)
      .bind(2, timeout_seconds)
      .execute();
  report.runs_interrupted = db_->changes();
  for (const std::string& owner : dead_owners) {
    db_->prepare(
           "UPDATE runs SET status = 'interrupted' WHERE status = 'running' AND id IN "
           "(SELECT run_id FROM job_claims WHERE owner = ? AND run_id IS NOT NULL)")
        .bind(1, owner)
        .execute();
    report.runs_interrupted += db_->changes();
  }
  transaction.commit();
  return report;
}

std::vector<JobClaimRecord> ResultsStore::find_job_claims(const std::string& now, bool live_only) const {
  SqliteStatement statement = db_->prepare(
      std::string("SELECT j.key, c.owner, c.host, c.pid, c.run_id, c.claimed_at, c.heartbeat_at, ") + kAgeOfHeartbeat +
      ", c.state, (julianday(?1) - julianday(c.claimed_at)) * 86400.0 FROM job_claims c JOIN jobs j ON j.id = c.job_id" + (live_only ? " WHERE c.state = 'live'" : "") +
      " ORDER BY c.state DESC, c.owner, c.claimed_at, j.key");
  statement.bind(1, now);
  std::vector<JobClaimRecord> claims;
  while (statement.step()) {
    JobClaimRecord claim;
    claim.key = statement.column_text(0);
    claim.owner = statement.column_text(1);
    claim.host = statement.column_text(2);
    claim.pid = statement.column_int(3);
    if (!statement.is_null(4)) claim.run_id = statement.column_int(4);
    claim.claimed_at = statement.column_text(5);
    claim.heartbeat_at = statement.column_text(6);
    claim.heartbeat_age_seconds = statement.column_double(7);
    claim.state = statement.column_text(8);
    claim.claim_age_seconds = statement.column_double(9);
    claims.push_back(std::move(claim));
  }
  return claims;
}

double ResultsStore::find_lease_seconds() const { return job_claims_sql::read_lease_seconds(*db_); }

void ResultsStore::update_lease_seconds(double seconds, const std::string& now) {
  if (!(seconds > 0.0) || !std::isfinite(seconds)) {
    throw StoreError(path_ + ": a lease must be a positive number of seconds");
  }
  SqliteTransaction transaction(*db_);
  db_->prepare("UPDATE claim_lease SET seconds = ?, changed_at = ? WHERE id = 1").bind(1, seconds).bind(2, now).execute();
  if (db_->changes() != 1) throw StoreError(path_ + ": damaged armfarm database: table claim_lease has no row");
  transaction.commit();
}

std::vector<RunningRunRecord> ResultsStore::find_running_runs(const std::string& now) const {
  SqliteStatement statement = db_->prepare(
      "SELECT r.id, s.name, r.shard, coalesce(r.host, ''), coalesce(r.pid, 0), r.started_at, "
      "(julianday(?1) - julianday(coalesce(r.heartbeat_at, r.started_at))) * 86400.0 "
      "FROM runs r JOIN sweeps s ON s.id = r.sweep_id WHERE r.status = 'running' ORDER BY r.id");
  statement.bind(1, now);
  std::vector<RunningRunRecord> runs;
  while (statement.step()) {
    RunningRunRecord run;
    run.id = statement.column_int(0);
    run.sweep = statement.column_text(1);
    run.shard = statement.column_optional_text(2);
    run.host = statement.column_text(3);
    run.pid = statement.column_int(4);
    run.started_at = statement.column_text(5);
    run.heartbeat_age_seconds = statement.column_double(6);
    runs.push_back(std::move(run));
  }
  return runs;
}

}  // namespace armfarm
