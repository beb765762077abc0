// Runs a command line as a child process for the CLI tests: one shell, stdout and stderr
// captured together, and an exit status that cannot mistake a crash for success.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace armfarm::test_support {

struct CommandResult {
  int exit_code;       ///< the command's exit status, or 128 + the signal that killed it
  std::string output;  ///< stdout and stderr, interleaved as written
};

/// Runs `command_line` with /bin/sh, its stderr merged into the captured stdout.
inline CommandResult run_command_line(const std::string& command_line) {
  FILE* pipe = popen((command_line + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return {127, "popen failed: " + command_line};
  std::string output;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  const int status = pclose(pipe);
  if (WIFSIGNALED(status)) return {128 + WTERMSIG(status), output};
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, output};
}

#ifdef ARMFARM_BINARY
/// Runs the armfarm binary under test with `arguments` (a shell-quoted argument string).
inline CommandResult run_armfarm(const std::string& arguments) {
  return run_command_line(std::string(ARMFARM_BINARY) + " " + arguments);
}
#endif

}  // namespace armfarm::test_support
