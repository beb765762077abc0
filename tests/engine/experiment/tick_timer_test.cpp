// TickLaps and ScopedSeconds (engine/experiment/tick_timer.hpp): the laps of a tick split its wall
// time without gaps or overlap (their sum is bounded by a steady_clock read around them), each
// tick is counted once, and a missing clock is never touched. No speed is asserted.
#include "engine/experiment/tick_timer.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace armfarm {
namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Spins until the steady clock has moved, so that every lap below is longer than zero.
void wait_for_the_clock() {
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() == start) {
  }
}

TEST(TickLaps, LapsOfATickSumToItsWallTimeAndCountTheTick) {
  TickClock clock;
  const auto before = std::chrono::steady_clock::now();
  {
    TickLaps laps(&clock);
    wait_for_the_clock();
    laps.lap(&TickClock::control);
    wait_for_the_clock();
    laps.lap(&TickClock::physics);
    wait_for_the_clock();
    laps.lap(&TickClock::control);  // a stage may lap twice in a tick: both add up
    TickLaps untimed(nullptr);        // no clock: laps go nowhere (and touch no null pointer)
    untimed.lap(&TickClock::physics);
    untimed.restart();
  }
  const auto after = std::chrono::steady_clock::now();
  EXPECT_EQ(clock.ticks, 1);
  EXPECT_GT(clock.control, 0.0);
  EXPECT_GT(clock.physics, 0.0);
  EXPECT_EQ(clock.learning, 0.0);
  EXPECT_LE(clock.total(), seconds_between(before, after));
}

TEST(TickLaps, RestartDropsTheTimeSinceTheLastLap) {
  TickClock clock;
  TickLaps laps(&clock);
  wait_for_the_clock();
  laps.lap(&TickClock::control);
  const double control = clock.control;
  wait_for_the_clock();
  const auto restarted = std::chrono::steady_clock::now();
  laps.restart();
  wait_for_the_clock();
  laps.lap(&TickClock::physics);
  const auto lapped = std::chrono::steady_clock::now();
  EXPECT_EQ(clock.control, control);
  EXPECT_LE(clock.physics, seconds_between(restarted, lapped));  // the time before restart() is in no stage
}

TEST(ScopedSeconds, AddsTheScopesDurationToTheTotal) {
  double total = 1.0;
  const auto before = std::chrono::steady_clock::now();
  {
    ScopedSeconds timed(&total);
    wait_for_the_clock();
  }
  const auto after = std::chrono::steady_clock::now();
  EXPECT_GT(total, 1.0);
  EXPECT_LE(total - 1.0, seconds_between(before, after));
  { ScopedSeconds untimed(nullptr); }  // a null total is left alone
}

}  // namespace
}  // namespace armfarm
