// Runs the built armfarm binary as a child process with fake jobs, for tests that stop, resume
// or kill runners (tests/faults/, tests/runner/cli/).
#pragma once

#include "support/command_line.hpp"
#include "support/fake_jobs_binary.hpp"
#include "support/text_file.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace armfarm::test_support {

struct ArmfarmProcess {
  pid_t pid = 0;
  std::string output_path;  ///< stdout and stderr
};

/// Starts `armfarm ARGS` (armfarm_fakejobs, running the fake job, when `fake_jobs`), stdout and stderr into
/// `output_path`.
inline ArmfarmProcess start_armfarm(const std::vector<std::string>& arguments, const std::string& output_path,
                                    bool fake_jobs = true) {
  const char* binary = fake_jobs ? ARMFARM_FAKE_JOBS_BINARY : ARMFARM_BINARY;
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(output_path.c_str(), "w", stdout)) _exit(126);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> argv = {const_cast<char*>(binary)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(binary, argv.data());
    _exit(127);
  }
  return {pid, output_path};
}

/// Waits for the process: its exit code, or 128 + the signal that ended it.
inline int wait_armfarm(const ArmfarmProcess& process) {
  int status = 0;
  waitpid(process.pid, &status, 0);
  return calc_exit_code(status);
}

inline std::string read_output(const ArmfarmProcess& process) { return read_text_file(process.output_path); }

}  // namespace armfarm::test_support
