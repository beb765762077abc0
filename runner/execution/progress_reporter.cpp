#include "runner/execution/progress_reporter.hpp"

#include <algorithm>
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

std::string make_progress_text(const ProgressFigures& figures) {
  std::string text = std::to_string(figures.done) + "/" + std::to_string(figures.total) + " done, " +
                     std::to_string(figures.failed) + " failed, " + std::to_string(figures.running) +
                     " running, elapsed " + make_duration_text(figures.elapsed_seconds) + ", ETA ";
  if (!figures.eta_seconds) {
    text += "?";
  } else if (figures.overdue == 0) {
    text += make_duration_text(*figures.eta_seconds);
  } else {
    // The overdue jobs' rest is unknown (counted as 0), so the figure is only a lower bound.
    text += (*figures.eta_seconds >= 1.0 ? "over " + make_duration_text(*figures.eta_seconds) : std::string("?")) +
            " (" + std::to_string(figures.overdue) + (figures.overdue == 1 ? " job" : " jobs") + " past " +
            (figures.overdue == 1 ? "its" : "their") + " estimate)";
  }
  if (!figures.running_keys.empty()) {
    text += "; running";
    for (const std::string& key : figures.running_keys) text += " " + key;
  }
  return text;
}

double calc_eta_seconds(double seconds_per_cost, double pending_cost,
                        const std::vector<std::pair<double, double>>& running, int threads) {
  double total = pending_cost * seconds_per_cost;
  double longest = 0.0;
  for (const auto& [cost, elapsed] : running) {
    const double rest = std::max(0.0, cost * seconds_per_cost - elapsed);
    total += rest;
    longest = std::max(longest, rest);
  }
  return std::max(total / std::max(1, threads), longest);
}

ProgressReporter::ProgressReporter(std::ostream* out, const ProgressConfig& config, std::vector<ProgressJob> jobs,
                                   int threads)
    : out_(out),
      config_([&] {
        ProgressConfig c = config;
        if (out == nullptr) c.style = ProgressStyle::quiet;
        return c;
      }()),
      jobs_(std::move(jobs)),
      threads_(std::max(1, threads)),
      start_(std::chrono::steady_clock::now()) {
  for (const ProgressJob& job : jobs_) pending_cost_ += job.cost;
  const bool ticks = config_.style == ProgressStyle::terminal ||
                     (config_.style == ProgressStyle::lines && config_.heartbeat_seconds > 0.0);
  if (ticks && !jobs_.empty()) ticker_ = std::thread([this] { tick_loop(); });
}

ProgressReporter::~ProgressReporter() { finish(); }

void ProgressReporter::job_started(std::size_t index) {
  std::lock_guard lock(mutex_);
  pending_cost_ -= jobs_.at(index).cost;
  running_.emplace_back(index, std::chrono::steady_clock::now());
}

void ProgressReporter::job_dropped(std::size_t index) {
  std::lock_guard lock(mutex_);
  running_.erase(std::remove_if(running_.begin(), running_.end(), [&](const auto& r) { return r.first == index; }),
                 running_.end());
}

void ProgressReporter::job_committed(std::size_t index, const std::string& status, double wall_seconds,
                                     const std::string& message) {
  std::lock_guard lock(mutex_);
  running_.erase(std::remove_if(running_.begin(), running_.end(), [&](const auto& r) { return r.first == index; }),
                 running_.end());
  ++committed_;
  if (status == "done") {
    ++done_;
  } else {
    ++failed_;
  }
  finished_wall_ += wall_seconds;
  finished_cost_ += jobs_.at(index).cost;
  if (config_.style == ProgressStyle::quiet) return;
  const int width = static_cast<int>(std::to_string(jobs_.size()).size());
  char prefix[64];
  std::snprintf(prefix, sizeof prefix, "[%*d/%zu] %-8s", width, committed_, jobs_.size(), status.c_str());
  const std::string line = std::string(prefix) + " " + jobs_.at(index).label + " (" + make_duration_text(wall_seconds) +
                           ")" + (message.empty() ? "" : ": " + message);
  if (config_.style == ProgressStyle::lines) {
    *out_ << line << "\n";
    out_->flush();
  } else {
    // Terminal: jobs that did not end done keep a line above the status line.
    if (status != "done") *out_ << "\r\033[K" << line << "\n";
    // At most 10 rewrites a second however fast jobs finish (the ticker refreshes each second).
    const auto now = std::chrono::steady_clock::now();
    if (status != "done" || now - last_line_ >= std::chrono::milliseconds(100)) {
      last_line_ = now;
      print_status_locked(false);
    }
  }
}

ProgressFigures ProgressReporter::figures() const {
  std::lock_guard lock(mutex_);
  return calc_figures_locked(std::chrono::steady_clock::now());
}

ProgressFigures ProgressReporter::calc_figures_locked(std::chrono::steady_clock::time_point now) const {
  ProgressFigures figures;
  figures.total = static_cast<int>(jobs_.size());
  figures.done = done_;
  figures.failed = failed_;
  figures.running = static_cast<int>(running_.size());
  figures.elapsed_seconds = std::chrono::duration<double>(now - start_).count();
  std::vector<std::pair<double, double>> running;
  for (const auto& [index, started] : running_) {
    running.emplace_back(jobs_[index].cost, std::chrono::duration<double>(now - started).count());
    figures.running_keys.push_back(jobs_[index].short_key);
  }
  if (committed_ > 0 && finished_cost_ > 0.0) {
    const double seconds_per_cost = finished_wall_ / finished_cost_;
    figures.eta_seconds = calc_eta_seconds(seconds_per_cost, std::max(0.0, pending_cost_), running, threads_);
    for (const auto& [cost, elapsed] : running) figures.overdue += elapsed >= cost * seconds_per_cost ? 1 : 0;
  }
  return figures;
}

void ProgressReporter::print_status_locked(bool heartbeat) {
  const std::string text = make_progress_text(calc_figures_locked(std::chrono::steady_clock::now()));
  if (config_.style == ProgressStyle::lines) {
    if (heartbeat) *out_ << "progress: " << text << "\n";
  } else if (config_.style == ProgressStyle::terminal) {
    const std::size_t width = static_cast<std::size_t>(std::max(20, config_.terminal_width) - 1);
    *out_ << "\r\033[K" << (text.size() > width ? text.substr(0, width - 3) + "..." : text);
  }
  out_->flush();
}

void ProgressReporter::tick_loop() {
  const double interval = config_.style == ProgressStyle::terminal ? 1.0 : config_.heartbeat_seconds;
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(interval));
  std::unique_lock lock(mutex_);
  auto next = std::chrono::steady_clock::now() + (config_.style == ProgressStyle::terminal ? std::chrono::steady_clock::duration(0) : period);
  for (;;) {
    if (wake_.wait_until(lock, next, [&] { return stopping_; })) return;
    print_status_locked(true);
    next += period;
  }
}

void ProgressReporter::finish() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
  std::lock_guard lock(mutex_);
  if (config_.style == ProgressStyle::terminal && !jobs_.empty()) {
    print_status_locked(false);
    *out_ << "\n";
    out_->flush();
  }
}

}  // namespace armfarm
