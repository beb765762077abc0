#pragma once
// Shared by the fuzz targets (tests/fuzz/README.md): the readers that take a path get each
// input through one scratch file in a per-process scratch folder under $TMPDIR.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm::fuzz {

/// $TMPDIR/armfarm_fuzz_<pid>/, created on the first call.
inline const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::filesystem::path path = std::filesystem::path(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") /
                                 ("armfarm_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return folder;
}

/// Writes `size` bytes to the scratch file "input<extension>" and returns its path.
inline std::string write_scratch(const std::uint8_t* data, std::size_t size, const std::string& extension) {
  const std::string path = (scratch_folder() / ("input" + extension)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace armfarm::fuzz
