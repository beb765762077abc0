// Progress a person can read: the ETA against its closed form, the status figures as jobs
// start and commit, heartbeat lines in a log, the terminal line and the cost estimate that
// weighs the ETA. The run's headline metric: run_headline_test.cpp.
#include "runner/execution/progress_reporter.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <regex>
#include <sstream>
#include <thread>

namespace armfarm {
namespace {

TEST(ProgressEta, SpreadsTheOpenCostOverTheThreadsButNeverBelowTheLongestRunningJob) {
  // 2 s per unit cost; 7 units pending over 2 threads: 7 s.
  EXPECT_DOUBLE_EQ(calc_eta_seconds(2.0, 7.0, {}, 2), 7.0);
  // A running job of cost 1 that ran 0.5 s has 1.5 s left: (12 + 1.5) / 2.
  EXPECT_DOUBLE_EQ(calc_eta_seconds(2.0, 6.0, {{1.0, 0.5}}, 2), 6.75);
  // A job past its estimate counts 0, not a negative time.
  EXPECT_DOUBLE_EQ(calc_eta_seconds(2.0, 0.0, {{1.0, 5.0}, {2.0, 1.0}}, 4), 3.0);
  // One long job left on 8 threads: its own rest, not an eighth of it.
  EXPECT_DOUBLE_EQ(calc_eta_seconds(1.0, 0.0, {{10.0, 2.0}}, 8), 8.0);
}

TEST(ProgressReporter, FiguresFollowStartsAndCommitsWeightedByCost) {
  std::vector<ProgressJob> jobs = {{"a", "aaaaaaaa", 1.0}, {"b", "bbbbbbbb", 1.0}, {"c", "cccccccc", 2.0}, {"d", "dddddddd", 4.0}};
  ProgressReporter reporter(nullptr, ProgressConfig{}, jobs, 2);
  ProgressFigures figures = reporter.figures();
  EXPECT_EQ(figures.total, 4);
  EXPECT_EQ(figures.done, 0);
  EXPECT_FALSE(figures.eta_seconds);  // nothing finished yet: no rate
  reporter.job_started(0);
  reporter.job_started(2);
  figures = reporter.figures();
  EXPECT_EQ(figures.running, 2);
  EXPECT_EQ(figures.running_keys, (std::vector<std::string>{"aaaaaaaa", "cccccccc"}));
  reporter.job_committed(0, "done", 2.0, "");  // 2 s for cost 1
  figures = reporter.figures();
  EXPECT_EQ(figures.done, 1);
  EXPECT_EQ(figures.running, 1);
  ASSERT_TRUE(figures.eta_seconds);
  // Pending b (1) and d (4): 10 s; c (cost 2, just started): 4 s less what it ran; over 2 threads.
  EXPECT_NEAR(*figures.eta_seconds, (10.0 + 4.0) / 2.0, 0.05);
  reporter.job_started(1);
  reporter.job_committed(1, "failed", 1.0, "boom");
  figures = reporter.figures();
  EXPECT_EQ(figures.done, 1);
  EXPECT_EQ(figures.failed, 1);
  // Rate now (2 + 1) / (1 + 1) = 1.5 s per unit: d 6 s and c 3 s over 2 threads = 4.5 s (> c alone, 3 s).
  EXPECT_NEAR(*figures.eta_seconds, 4.5, 0.05);
}

TEST(ProgressReporter, ALogGetsALinePerCommittedJobAndHeartbeatsWithTheEta) {
  std::ostringstream out;
  ProgressConfig config;
  config.style = ProgressStyle::lines;
  config.heartbeat_seconds = 0.02;
  {
    ProgressReporter reporter(&out, config, {{"a k=1", "aaaaaaaa", 1.0}, {"b k=2", "bbbbbbbb", 1.0}}, 1);
    reporter.job_started(0);
    reporter.job_committed(0, "done", 0.5, "");
    reporter.job_started(1);
    std::this_thread::sleep_for(std::chrono::milliseconds(120));
    reporter.job_committed(1, "diverged", 0.25, "joint 1 left its range");
    reporter.finish();
  }
  const std::string text = out.str();
  EXPECT_NE(text.find("[1/2] done     a k=1 (0.500 s)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("[2/2] diverged b k=2 (0.250 s): joint 1 left its range\n"), std::string::npos) << text;
  EXPECT_NE(text.find("progress: 1/2 done, 0 failed, 1 running, elapsed "), std::string::npos) << text;
  EXPECT_NE(text.find(", ETA "), std::string::npos) << text;
  EXPECT_NE(text.find("; running bbbbbbbb\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("\r"), std::string::npos) << "no terminal control characters in a log";
  EXPECT_TRUE(std::regex_search(text, std::regex(R"(progress: 1/2 done.*, ETA [0-9])"))) << "a heartbeat after the first job has an ETA: " << text;
}

TEST(ProgressReporter, ATerminalGetsOneRewrittenLineAndKeepsFailures) {
  std::ostringstream out;
  ProgressConfig config;
  config.style = ProgressStyle::terminal;
  config.terminal_width = 60;
  {
    ProgressReporter reporter(&out, config, {{"a", "aaaaaaaa", 1.0}, {"b", "bbbbbbbb", 1.0}}, 2);
    reporter.job_started(0);
    reporter.job_started(1);
    reporter.job_committed(0, "done", 0.1, "");
    reporter.job_committed(1, "timeout", 0.2, "stopped");
  }
  const std::string text = out.str();
  EXPECT_NE(text.find("\r\033[K"), std::string::npos);
  EXPECT_EQ(text.find("[1/2] done"), std::string::npos) << "done jobs do not get lines of their own";
  EXPECT_NE(text.find("[2/2] timeout  b (0.200 s): stopped\n"), std::string::npos) << text;
  EXPECT_NE(text.find("1/2 done, 1 failed, 0 running"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');
  // No status line wider than the terminal.
  std::size_t start = 0;
  while ((start = text.find("\r\033[K", start)) != std::string::npos) {
    start += 4;
    const std::size_t end = text.find_first_of("\r\n", start);
    EXPECT_LT((end == std::string::npos ? text.size() : end) - start, 60u);
  }
}

TEST(ProgressText, DurationsAndTheStatusLine) {
  EXPECT_EQ(make_duration_text(0.5), "0.500 s");
  EXPECT_EQ(make_duration_text(12.34), "12.3 s");
  EXPECT_EQ(make_duration_text(245.0), "4 min 05 s");
  EXPECT_EQ(make_duration_text(3720.0), "1 h 02 min");
  ProgressFigures figures;
  figures.total = 12;
  figures.done = 3;
  figures.failed = 1;
  figures.running = 2;
  figures.elapsed_seconds = 245.0;
  figures.eta_seconds = 70.0;
  figures.running_keys = {"3f2a1b7c", "9ab01234"};
  EXPECT_EQ(make_progress_text(figures), "3/12 done, 1 failed, 2 running, elapsed 4 min 05 s, ETA 1 min 10 s; running 3f2a1b7c 9ab01234");
  figures.eta_seconds.reset();
  figures.running_keys.clear();
  EXPECT_EQ(make_progress_text(figures), "3/12 done, 1 failed, 2 running, elapsed 4 min 05 s, ETA ?");
  // Jobs past their estimate make the ETA a lower bound, and a "0.000 s" no answer at all.
  figures.eta_seconds = 70.0;
  figures.overdue = 1;
  EXPECT_EQ(make_progress_text(figures),
            "3/12 done, 1 failed, 2 running, elapsed 4 min 05 s, ETA over 1 min 10 s (1 job past its estimate)");
  figures.eta_seconds = 0.0;
  figures.overdue = 2;
  EXPECT_EQ(make_progress_text(figures), "3/12 done, 1 failed, 2 running, elapsed 4 min 05 s, ETA ? (2 jobs past their estimate)");
}

TEST(ProgressReporter, CountsTheRunningJobsPastTheirEstimate) {
  std::vector<ProgressJob> jobs = {{"a", "aaaaaaaa", 1.0}, {"b", "bbbbbbbb", 1.0}};
  ProgressReporter reporter(nullptr, ProgressConfig{}, jobs, 1);
  reporter.job_started(0);
  reporter.job_committed(0, "done", 1e-6, "");  // 1 µs per unit cost: b is overdue at once
  reporter.job_started(1);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  const ProgressFigures figures = reporter.figures();
  EXPECT_EQ(figures.overdue, 1);
  ASSERT_TRUE(figures.eta_seconds);
  EXPECT_EQ(*figures.eta_seconds, 0.0);
}

}  // namespace
}  // namespace armfarm
