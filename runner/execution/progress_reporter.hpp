#pragma once
// What a running sweep tells its user while it runs. On a terminal: one status line rewritten
// in place (done/failed/running of total, elapsed, ETA, the running jobs' short keys), refreshed
// every second, with a permanent line for each job that did not end `done`. In a log (not a
// terminal): one line per finished job plus a heartbeat line with the same figures every
// `heartbeat_seconds`. A job counts as finished only once its result is committed
// (job_committed), so nothing is reported `done` that the database does not hold.
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

namespace armfarm {

enum class ProgressStyle { terminal, lines, quiet };

/// How a sweep's progress is shown (`armfarm run` picks the style from isatty and --quiet).
struct ProgressConfig {
  ProgressStyle style = ProgressStyle::quiet;
  double heartbeat_seconds = 30.0;  ///< lines style: a status line this often; 0 = none
  int terminal_width = 100;         ///< terminal style: the status line is cut to this many columns
};

/// One job the reporter follows.
struct ProgressJob {
  std::string label;      ///< short key and varying parameters (make_job_label)
  std::string short_key;  ///< first 8 hex digits of the key
  double cost = 1.0;      ///< relative cost estimate (RunOptions::job_costs, job_cost.hpp), > 0
};

/// The figures of a status line, at one moment.
struct ProgressFigures {
  int total = 0;
  int done = 0;
  int failed = 0;   ///< committed with any status other than done
  int running = 0;
  double elapsed_seconds = 0.0;
  std::optional<double> eta_seconds;  ///< none before the first job finished
  int overdue = 0;  ///< running jobs already past their estimate: the ETA is then a lower bound
  std::vector<std::string> running_keys;  ///< short keys, in start order
};

class ProgressReporter {
 public:
  /// `out` may be null (then nothing is printed, whatever the style). `threads` is the number
  /// of jobs that run at once (the ETA divides the remaining work by it).
  ProgressReporter(std::ostream* out, const ProgressConfig& config, std::vector<ProgressJob> jobs, int threads);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  /// Job `index` (into the constructor's list) started (any thread).
  void job_started(std::size_t index);
  /// Job `index` ended and its result is committed (any thread, after the commit).
  void job_committed(std::size_t index, const std::string& status, double wall_seconds, const std::string& message);
  /// Job `index` ended without a committed result (interrupted, or its commit failed).
  void job_dropped(std::size_t index);
  /// Stops the refresh and ends the status line (terminal style). Idempotent.
  void finish();

  ProgressFigures figures() const;

 private:
  ProgressFigures calc_figures_locked(std::chrono::steady_clock::time_point now) const;
  void print_status_locked(bool heartbeat);
  void tick_loop();

  std::ostream* out_;
  const ProgressConfig config_;
  const std::vector<ProgressJob> jobs_;
  const int threads_;
  const std::chrono::steady_clock::time_point start_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  int committed_ = 0;
  int done_ = 0;
  int failed_ = 0;
  double finished_wall_ = 0.0;  ///< Σ wall time of committed jobs, s
  double finished_cost_ = 0.0;  ///< Σ cost of committed jobs
  double pending_cost_ = 0.0;   ///< Σ cost of the jobs not started
  /// Running jobs: index and start time, in start order.
  std::vector<std::pair<std::size_t, std::chrono::steady_clock::time_point>> running_;
  std::chrono::steady_clock::time_point last_line_{};  ///< terminal: when the status line was last rewritten
  std::thread ticker_;
};

/// "0.512 s", "12.3 s", "4 min 05 s", "1 h 02 min".
std::string make_duration_text(double seconds);

/// "3/12 done, 1 failed, 2 running, elapsed 4 min 05 s, ETA 1 min 10 s" (ETA "?" before the
/// first job finished), then "; running 3f2a1b7c 9ab01234" when jobs run. With jobs past
/// their estimate: "ETA over 1 min 10 s (1 job past its estimate)", or "ETA ? (…)" below 1 s.
std::string make_progress_text(const ProgressFigures& figures);

/// Remaining wall time of a sweep: the finished jobs' seconds per unit cost times the cost
/// still open, spread over `threads` but never shorter than the longest running job's rest.
/// `pending_cost`: Σ cost of the jobs not started; `running`: (cost, seconds run so far) of
/// each running job, which counts what its estimate has left, never less than 0.
double calc_eta_seconds(double seconds_per_cost, double pending_cost,
                        const std::vector<std::pair<double, double>>& running, int threads);

}  // namespace armfarm
