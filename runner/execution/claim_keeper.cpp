#include "runner/execution/claim_keeper.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

namespace armfarm {

std::string find_this_host() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

bool is_runner_gone(const std::string& host, std::int64_t pid) {
  if (pid <= 0 || host.empty() || host != find_this_host()) return false;
  return kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH;
}

ClaimOwner make_claim_owner(const std::string& host, std::int64_t run_id, const std::string& sweep) {
  ClaimOwner owner;
  owner.host = host.empty() ? find_this_host() : host;
  owner.pid = static_cast<std::int64_t>(getpid());
  owner.owner = make_claim_owner_id(owner.host, owner.pid);
  owner.run_id = run_id;
  owner.sweep = sweep;
  return owner;
}

namespace {

// Owners of live claims that ran on this host under a pid that no longer exists (a runner killed
// or stopped after a failed commit): their claims need not wait for the heartbeat timeout. A
// reused pid only makes a dead owner look alive, which falls back to the timeout.
std::vector<std::string> find_dead_local_owners(const ResultsStore& store, const ClaimOwner& self, const std::string& now) {
  std::set<std::string> dead;
  for (const JobClaimRecord& claim : store.find_job_claims(now, true)) {
    if (claim.host == self.host && claim.owner != self.owner && is_runner_gone(claim.host, claim.pid)) {
      dead.insert(claim.owner);
    }
  }
  return {dead.begin(), dead.end()};
}

}  // namespace

ClaimKeeper::ClaimKeeper(const std::string& db_path, const ClaimOwner& owner, const ClaimConfig& config, bool force,
                         const std::string& run_started_at)
    : owner_(owner),
      config_(config),
      redo_done_before_(force ? std::optional<std::string>(run_started_at) : std::nullopt),
      store_(ResultsStore::open(db_path, ResultsStore::Mode::read_write)) {
  const std::string now = make_utc_timestamp();
  lease_seconds_ = store_.find_lease_seconds();
  stale_at_start_ = store_.interrupt_stale_claims(now, owner_.owner, find_dead_local_owners(store_, owner_, now));
  store_.refresh_claims(owner_, make_utc_timestamp());
  thread_ = std::thread([this] { heartbeat_loop(); });
}

ClaimKeeper::~ClaimKeeper() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

ClaimAttempt ClaimKeeper::claim(const std::string& key) {
  std::lock_guard store_lock(store_mutex_);
  const ClaimAttempt attempt =
      store_.claim_job(key, owner_, make_utc_timestamp(), redo_done_before_);
  std::lock_guard lock(mutex_);
  if (attempt.result == ClaimResult::claimed) {
    held_[key] = attempt.generation;
    lost_.erase(key);
  }
  if (!attempt.taken_over.empty()) ++taken_over_;
  return attempt;
}

std::int64_t ClaimKeeper::generation(const std::string& key) const {
  std::lock_guard lock(mutex_);
  const auto found = held_.find(key);
  return found == held_.end() ? 0 : found->second;
}

bool ClaimKeeper::lost(const std::string& key) const {
  std::lock_guard lock(mutex_);
  return lost_.count(key) > 0;
}

void ClaimKeeper::forget(const std::string& key) {
  std::lock_guard lock(mutex_);
  held_.erase(key);
}

bool ClaimKeeper::failed() const {
  std::lock_guard lock(mutex_);
  return error_ != nullptr;
}

void ClaimKeeper::rethrow_error() const {
  std::lock_guard lock(mutex_);
  if (error_) std::rethrow_exception(error_);
}

int ClaimKeeper::taken_over() const {
  std::lock_guard lock(mutex_);
  return taken_over_;
}

void ClaimKeeper::wait_poll(const std::atomic<bool>& stop) const {
  double lease = 0.0;
  {
    std::lock_guard lock(mutex_);
    lease = lease_seconds_;
  }
  const double interval = std::min(config_.poll_seconds, lease / config_.heartbeats_per_lease);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(interval);
  while (!stop.load() && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void ClaimKeeper::heartbeat_loop() {
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      const auto interval = std::chrono::duration<double>(lease_seconds_ / config_.heartbeats_per_lease);
      if (wake_.wait_for(lock, interval, [&] { return closing_; })) return;
    }
    try {
      // Compared under the store lock, so that no claim lands between the refresh and the check.
      std::lock_guard store_lock(store_mutex_);
      const std::vector<std::string> still_held = store_.refresh_claims(owner_, make_utc_timestamp());
      const double lease = store_.find_lease_seconds();  // `armfarm lease` may have changed it
      std::lock_guard lock(mutex_);
      lease_seconds_ = lease;
      for (const auto& [key, generation] : held_) {
        if (!std::binary_search(still_held.begin(), still_held.end(), key)) lost_.insert(key);
      }
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      return;
    }
  }
}

}  // namespace armfarm
