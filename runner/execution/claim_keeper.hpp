#pragma once
// A runner's side of job claims (results/job_claims.hpp): before a job runs, its worker claims
// it here; a thread of its own refreshes the heartbeats of this process's claims and of its
// `runs` row every lease / 6 (the lease is the database's, results/job_claims.hpp, read again at
// every beat), and notices claims another runner took over (the job is then stopped). Whatever
// the keeper notices, the store's fence decides: a result commits only under its claim's token. Releasing a claim happens with the job's result, in the
// writer's transaction (JobBatch::claim_owner).
//
// The keeper has its own connection to the database, apart from the ResultWriter's: a claim must
// be answered before the job may start, and heartbeats must not wait behind result batches.
// Both connections are serialised by SQLite's file lock (busy timeout 10 s).
#include "results/results_store.hpp"

#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <map>
#include <set>
#include <string>
#include <thread>

namespace armfarm {

/// How a runner keeps its claims. The lease itself (after how long without a heartbeat a claim
/// is stale) is not here: it is the database's (`armfarm lease DB SECONDS`), so that every
/// runner of a file judges by the same one.
struct ClaimConfig {
  /// Heartbeats per lease: a live runner refreshes every lease / this.
  double heartbeats_per_lease = 6.0;
  /// How long a runner waits between looks at jobs another runner holds, s (at most
  /// lease / heartbeats_per_lease).
  double poll_seconds = 1.0;
};

/// This host's name as claims record it (gethostname()).
std::string find_this_host();

/// True when the process `pid` of a runner on `host` is known to be gone: `host` is this host
/// and no process has that pid. A pid reused by another process, or a runner on another host,
/// is not known gone (only its heartbeat's age can tell); a live runner is never called gone.
bool is_runner_gone(const std::string& host, std::int64_t pid);

/// This process as a claim owner: host (gethostname() when empty), pid, a unique owner id.
ClaimOwner make_claim_owner(const std::string& host, std::int64_t run_id, const std::string& sweep);

class ClaimKeeper {
 public:
  /// Opens its connection, marks stale claims and runs interrupted, starts the heartbeat thread.
  /// `force`: done jobs are claimed again if they finished before `run_started_at`.
  ClaimKeeper(const std::string& db_path, const ClaimOwner& owner, const ClaimConfig& config, bool force,
              const std::string& run_started_at);
  ~ClaimKeeper();
  ClaimKeeper(const ClaimKeeper&) = delete;
  ClaimKeeper& operator=(const ClaimKeeper&) = delete;

  /// Tries to claim the job (thread-safe). Throws StoreError.
  ClaimAttempt claim(const std::string& key);
  /// The fencing token of this process's claim of `key` (0 when it holds none).
  std::int64_t generation(const std::string& key) const;
  /// True once another runner took over this process's claim of `key` (the job should stop).
  bool lost(const std::string& key) const;
  /// Forgets a claim locally (the store releases it with the job's result or abandonment).
  void forget(const std::string& key);
  /// True once a heartbeat failed to be written (the runner then stops taking jobs).
  bool failed() const;
  /// Rethrows the heartbeat thread's first error, if any.
  void rethrow_error() const;
  /// Sleeps one poll interval or until `stop` is set.
  void wait_poll(const std::atomic<bool>& stop) const;

  const ClaimOwner& owner() const { return owner_; }
  const StaleClaimReport& stale_at_start() const { return stale_at_start_; }
  /// Claims of other runners found stale and taken over by claim().
  int taken_over() const;

 private:
  void heartbeat_loop();

  ClaimOwner owner_;
  ClaimConfig config_;
  std::optional<std::string> redo_done_before_;
  mutable std::mutex store_mutex_;  // guards store_
  ResultsStore store_;
  StaleClaimReport stale_at_start_;

  mutable std::mutex mutex_;  // guards what follows
  std::condition_variable wake_;
  bool closing_ = false;
  std::map<std::string, std::int64_t> held_;  // key -> fencing token
  std::set<std::string> lost_;
  double lease_seconds_ = 60.0;
  int taken_over_ = 0;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace armfarm
