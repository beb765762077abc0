// Scratch file names for tests that write an input file and read it back.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace armfarm::test_support {

/// A path in the system's temporary folder that no other test process uses: `name` prefixed
/// with "armfarm-<pid>-". ctest runs every test case as a process of its own, several at once,
/// so a fixed name shared by two cases of one file lets one case read the other's bytes.
inline std::string scratch_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("armfarm-" + std::to_string(::getpid()) + "-" + name)).string();
}

}  // namespace armfarm::test_support
