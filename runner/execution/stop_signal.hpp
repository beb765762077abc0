#pragma once
// Ctrl-C for a running sweep: while a StopSignalScope lives, SIGINT, SIGTERM and SIGUSR1 (Slurm's
// warning before a time limit) set a flag that
// the runner polls (stop taking jobs, ask running ones to stop, record what finished). The
// first signal restores the default handlers, so a second Ctrl-C ends the process at once
// (the database stays consistent either way: every batch is one transaction).
#include <atomic>

namespace armfarm {

class StopSignalScope {
 public:
  StopSignalScope();
  ~StopSignalScope();
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;

  /// Set once SIGINT, SIGTERM or SIGUSR1 arrived.
  const std::atomic<bool>& stop_requested() const;
  /// Set once SIGINT or SIGTERM arrived: a stop that no grace waits for (SIGUSR1 is Slurm's
  /// warning, with time left; RunOptions::stop_grace_seconds).
  const std::atomic<bool>& stop_at_once() const;
  /// The signal received (0 if none).
  int signal_number() const;
};

}  // namespace armfarm
