// Scratch file names for tests that write an input file and read it back.
#pragma once

#include <gtest/gtest.h>
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

/// A fresh, empty folder for the running test case: "armfarm_<prefix>_<pid>_<test name>" in the
/// system's temporary folder, emptied first if a crashed run left it. The caller removes it.
inline std::filesystem::path make_scratch_folder(const std::string& prefix) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("armfarm_" + prefix + "_" + std::to_string(::getpid()) + "_" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

/// A fixture whose every test case has a fresh scratch folder, `folder_`
/// (make_scratch_folder(prefix), made before SetUp and removed after TearDown); path(name) is a
/// file in it. A derived fixture passes its prefix: `MyTest() : ScratchFolderTest("mine") {}`.
class ScratchFolderTest : public ::testing::Test {
 protected:
  explicit ScratchFolderTest(const std::string& prefix) : folder_(make_scratch_folder(prefix)) {}
  ~ScratchFolderTest() override {
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }

  const std::filesystem::path folder_;
};

}  // namespace armfarm::test_support
