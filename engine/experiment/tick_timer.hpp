#pragma once
// Wall-clock timers of a control pass, kept out of its physics: TickLaps splits one tick's wall
// time among the TickClock stages (control_pass.hpp), ScopedSeconds adds a scope's duration to a
// counter (the pass's learner updates, and batch training's updates and predictions,
// batch_training.cpp). Both do nothing when given no clock. Seconds, std::chrono::steady_clock.
#include "engine/experiment/control_pass.hpp"

#include <chrono>

namespace armfarm {

/// One tick's stage timing, scoped to the tick: construction starts the tick (and counts it),
/// lap(slot) adds the time since the previous lap (or the start) to `slot`, so the laps of a
/// tick sum to its wall time up to the last lap. restart() drops the time since the previous lap
/// (work that belongs to no stage of this tick, e.g. a learning checkpoint's passes).
class TickLaps {
 public:
  explicit TickLaps(TickClock* clock) : clock_(clock) {
    if (!clock_) return;
    ++clock_->ticks;
    last_ = Clock::now();
  }
  void lap(double TickClock::*slot) {
    if (!clock_) return;
    const Clock::time_point now = Clock::now();
    clock_->*slot += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }
  void restart() {
    if (clock_) last_ = Clock::now();
  }

 private:
  using Clock = std::chrono::steady_clock;
  TickClock* clock_;
  Clock::time_point last_{};
};

/// Adds the seconds from construction to destruction to `*total` (nothing when null).
class ScopedSeconds {
 public:
  explicit ScopedSeconds(double* total) : total_(total), start_(total ? Clock::now() : Clock::time_point{}) {}
  ~ScopedSeconds() {
    if (total_) *total_ += std::chrono::duration<double>(Clock::now() - start_).count();
  }
  ScopedSeconds(const ScopedSeconds&) = delete;
  ScopedSeconds& operator=(const ScopedSeconds&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  double* total_;
  Clock::time_point start_;
};

}  // namespace armfarm
