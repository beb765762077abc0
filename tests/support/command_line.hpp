// Runs a command line as a child process for the CLI tests: one shell, stdout and stderr
// captured together, and an exit status that cannot mistake a crash for success.
#pragma once

#include "support/fake_jobs_binary.hpp"

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace armfarm::test_support {

struct CommandResult {
  int exit_code;       ///< the command's exit status, or 128 + the signal that killed it
  std::string output;  ///< stdout and stderr, interleaved as written
};

/// The exit code of a child's wait status: its exit status, 128 + the signal that killed it, or
/// 128 when it neither exited nor was killed (never 0 for a crash).
inline int calc_exit_code(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
  return 128;
}

/// Runs `command_line` with /bin/sh, its stderr merged into the captured stdout (every byte,
/// NULs included).
inline CommandResult run_command_line(const std::string& command_line) {
  FILE* pipe = popen((command_line + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return {127, "popen failed: " + command_line};
  std::string output;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  return {calc_exit_code(pclose(pipe)), output};
}

#ifdef ARMFARM_BINARY
/// Runs the armfarm binary under test with `arguments` (a shell-quoted argument string).
inline CommandResult run_armfarm(const std::string& arguments) {
  return run_command_line(std::string(ARMFARM_BINARY) + " " + arguments);
}

/// Runs the test binary armfarm_fakejobs (the same command line, running the runner's fake job).
inline CommandResult run_armfarm_with_fake_jobs(const std::string& arguments) {
  return run_command_line(std::string(ARMFARM_FAKE_JOBS_BINARY) + " " + arguments);
}
#endif

}  // namespace armfarm::test_support
