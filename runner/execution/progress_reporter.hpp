#pragma once
// What a running sweep tells its user: on a terminal one progress line rewritten in place
// (done/total, failed, elapsed, ETA); otherwise one plain log line per finished job.
#include <chrono>
#include <mutex>
#include <ostream>
#include <string>

namespace armfarm {

enum class ProgressStyle { terminal, lines, quiet };

class ProgressReporter {
 public:
  /// `out` may be null (then nothing is printed, whatever the style).
  ProgressReporter(std::ostream* out, ProgressStyle style, int total);

  /// A job ended (any thread). `label` is its short key and varying parameters.
  void update_finished(const std::string& label, const std::string& status, double wall_seconds,
                       const std::string& message);
  /// Ends the progress line (terminal style).
  void finish();

 private:
  void print_line(bool force);

  std::ostream* out_;
  const ProgressStyle style_;
  const int total_;
  int finished_ = 0;
  int not_done_ = 0;
  std::mutex mutex_;
  const std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

/// "12.3 s", "4 min 05 s", "1 h 02 min".
std::string make_duration_text(double seconds);

}  // namespace armfarm
