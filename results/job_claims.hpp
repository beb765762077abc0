#pragma once
// Job claims: how several `armfarm run` processes share one database file without running a job
// twice. A runner claims a job (one row of `job_claims`: owner, host, pid, run, heartbeat, and a
// fencing token `generation` that grows with every claim of the job) in one transaction before
// it runs it; its result commits only in a transaction that finds that token still the job's
// current live claim, and releases the claim there (ResultsStore::insert_job_batch). A runner
// refreshes the heartbeats of its live claims and of its `runs` row; a live claim whose heartbeat
// is older than the file's lease (claim_lease, one value for every runner) is stale: it is marked
// `interrupted` (with its run) and the job may be claimed again, under a new token.
// Schema and the rules in results/README.md ("Job claims"). Times are UTC ISO-8601 text, ages s.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

class SqliteConnection;

/// Who claims: one per `armfarm run` process.
struct ClaimOwner {
  std::string owner;         ///< unique per process: "host:pid:start time", see make_claim_owner_id
  std::string host;
  std::int64_t pid = 0;
  std::int64_t run_id = 0;   ///< the `runs` row of the process's run
  std::string sweep;         ///< written to jobs.sweep on a claim (the sweep that runs the job)
};

/// What a claim attempt found.
enum class ClaimResult {
  claimed,            ///< the job is this owner's now: status `running`, attempts + 1
  done,               ///< the job is done (by any runner); nothing to do
  claimed_elsewhere,  ///< another owner holds a live claim whose heartbeat is fresh
};

struct ClaimAttempt {
  ClaimResult result = ClaimResult::claimed;
  std::string other_owner;   ///< claimed_elsewhere: the holder
  std::string taken_over;    ///< claimed after marking this owner's stale claim interrupted ("" if none)
  /// claimed: the claim's fencing token (jobs.claim_generation, one more than the job's last
  /// claim had); the result commits only while it is still the job's current live claim.
  std::int64_t generation = 0;
};

/// One row of `job_claims` as `status` shows it.
struct JobClaimRecord {
  std::string key;        ///< the job's key
  std::string owner, host;
  std::int64_t pid = 0;
  std::optional<std::int64_t> run_id;
  std::string claimed_at, heartbeat_at;
  double heartbeat_age_seconds = 0.0;  ///< at the `now` given to the query
  double claim_age_seconds = 0.0;      ///< since claimed_at, at `now`
  std::string state;                   ///< live, interrupted
};

/// One `runs` row still marked `running`, as `status` shows it: its process may be alive, or
/// may have died without closing it (a SIGKILL) until a later run marks it interrupted.
struct RunningRunRecord {
  std::int64_t id = 0;
  std::string sweep;
  std::optional<std::string> shard;   ///< "2/4"
  std::string host;                   ///< runs.host ("" when not recorded)
  std::int64_t pid = 0;               ///< 0 when not recorded (a build before claims)
  std::string started_at;
  double heartbeat_age_seconds = 0.0; ///< since heartbeat_at (or started_at without one), at `now`
};

/// What a scan for stale claims changed.
struct StaleClaimReport {
  int claims_interrupted = 0;  ///< stale live claims marked interrupted (their jobs went back to pending)
  int runs_interrupted = 0;    ///< `running` runs rows whose heartbeat is stale, marked interrupted
};

/// "host:pid:nanoseconds since the epoch in hex": unique per process on a host.
std::string make_claim_owner_id(const std::string& host, std::int64_t pid);

namespace job_claims_sql {
/// The migration step that adds claims (appended to the store's migration list).
extern const char* const kMigration;
/// The migration step that fences claims (schema 5): the one-row `claim_lease` table (the
/// lease, s, shared by every runner of the file), jobs.claim_generation, job_claims.generation.
extern const char* const kFencingMigration;
/// Within the caller's transaction: true when `owner` holds the live claim of job `key` with
/// fencing token `generation` and no later claim was made (the only state in which its result
/// may commit).
bool is_claim_current(SqliteConnection& db, const std::string& key, const std::string& owner,
                      std::int64_t generation);
/// The file's lease (claim_lease.seconds).
double read_lease_seconds(SqliteConnection& db);
/// Within the caller's transaction: releases `owner`'s live claim of job `job_id`; true when it
/// held one.
bool release_claim(SqliteConnection& db, std::int64_t job_id, const std::string& owner);
}  // namespace job_claims_sql

}  // namespace armfarm
