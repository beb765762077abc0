#include "runner/execution/progress_reporter.hpp"

#include <cstdio>

namespace armfarm {

std::string make_duration_text(double seconds) {
  char text[32];
  if (seconds < 10.0) {
    std::snprintf(text, sizeof text, "%.3f s", seconds);
  } else if (seconds < 60.0) {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  } else if (seconds < 3600.0) {
    std::snprintf(text, sizeof text, "%d min %02d s", static_cast<int>(seconds / 60), static_cast<int>(seconds) % 60);
  } else {
    std::snprintf(text, sizeof text, "%d h %02d min", static_cast<int>(seconds / 3600),
                  static_cast<int>(seconds / 60) % 60);
  }
  return text;
}

ProgressReporter::ProgressReporter(std::ostream* out, ProgressStyle style, int total)
    : out_(out), style_(out != nullptr ? style : ProgressStyle::quiet), total_(total), start_(std::chrono::steady_clock::now()), last_print_(start_) {}

void ProgressReporter::update_finished(const std::string& label, const std::string& status, double wall_seconds,
                                       const std::string& message) {
  std::lock_guard lock(mutex_);
  ++finished_;
  if (status != "done") ++not_done_;
  if (style_ == ProgressStyle::lines) {
    const int width = static_cast<int>(std::to_string(total_).size());
    char prefix[64];
    std::snprintf(prefix, sizeof prefix, "[%*d/%d] %-8s", width, finished_, total_, status.c_str());
    *out_ << prefix << " " << label << " (" << make_duration_text(wall_seconds) << ")"
         << (message.empty() ? "" : ": " + message) << "\n";
    out_->flush();
  } else if (style_ == ProgressStyle::terminal) {
    print_line(finished_ == total_);
  }
}

void ProgressReporter::print_line(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_print_ < std::chrono::milliseconds(100)) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::string eta = "?";
  if (finished_ > 0) eta = make_duration_text(elapsed / finished_ * (total_ - finished_));
  *out_ << "\r\033[K" << finished_ << "/" << total_ << " jobs, " << not_done_ << " failed, elapsed "
       << make_duration_text(elapsed) << ", ETA " << eta;
  out_->flush();
}

void ProgressReporter::finish() {
  std::lock_guard lock(mutex_);
  if (style_ == ProgressStyle::terminal && total_ > 0) {
    print_line(true);
    *out_ << "\n";
    out_->flush();
  }
}

}  // namespace armfarm
