// Spec files and includes go through the confined reader: /dev/zero, a FIFO, a directory or an
// oversized include is refused at once with the including spec and the path named, and a file
// that is not JSON is refused without its content in the message.
#include "runner/execution/fake_job.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class SpecInputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test_support::make_scratch_folder("spec_inputs");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // The spec's error lines joined by newlines ("" when it loads).
  std::string errors_of(const std::string& path) {
    try {
      load_sweep_spec(path, make_fake_job_config_schema());
    } catch (const SpecError& error) {
      std::string all;
      for (const std::string& line : error.lines()) all += line + "\n";
      return all;
    }
    return "";
  }

  std::string spec_including(const std::string& include) {
    return write("spec.json", "{\"name\": \"s\", \"include\": [\"" + include + "\"]}");
  }

  fs::path dir_;
};

TEST_F(SpecInputFiles, DevZeroIncludeIsRefusedAtOnce) {
  const std::string spec = spec_including("/dev/zero");
  const auto start = std::chrono::steady_clock::now();
  const std::string errors = errors_of(spec);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_EQ(errors, spec + ": include: /dev/zero: is a character device, not a regular file\n");
}

TEST_F(SpecInputFiles, FifoIncludeIsRefusedWithoutHanging) {
  ASSERT_EQ(::mkfifo((dir_ / "pipe.json").c_str(), 0600), 0);
  const std::string spec = spec_including("pipe.json");
  // Nobody writes to the FIFO: reading it would block until ctest's timeout.
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "pipe.json").string() + ": is a FIFO (named pipe), not a regular file\n");
}

TEST_F(SpecInputFiles, DirectoryIncludeAndDirectorySpecAreRefused) {
  fs::create_directories(dir_ / "folder");
  const std::string spec = spec_including("folder");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "folder").string() + ": is a directory, not a regular file\n");
  EXPECT_EQ(errors_of((dir_ / "folder").string()), (dir_ / "folder").string() + ": is a directory, not a regular file\n");
}

TEST_F(SpecInputFiles, OversizedIncludeIsRefusedWithItsSizeAndCap) {
  const std::string big = write("big.json", std::string((16u << 20) + 1, ' '));
  const std::string spec = spec_including("big.json");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + big + ": is 16777217 bytes, over the 16 MiB cap for JSON files\n");
}

TEST_F(SpecInputFiles, NonJsonIncludeIsNamedByLineNotQuoted) {
  write("passwd", "root:x:0:0:root:/root:/bin/bash\nsecret-user:x:1000:1000::/home/s:/bin/sh\n");
  const std::string errors = errors_of(spec_including("passwd"));
  EXPECT_NE(errors.find("passwd: line 1, column 1: not valid JSON"), std::string::npos) << errors;
  EXPECT_EQ(errors.find("root"), std::string::npos) << errors;
  EXPECT_EQ(errors.find("'r'"), std::string::npos) << errors;
}

TEST_F(SpecInputFiles, MissingIncludeNamesThePath) {
  const std::string spec = spec_including("nowhere.json");
  EXPECT_EQ(errors_of(spec), spec + ": include: " + (dir_ / "nowhere.json").string() + ": no such file\n");
}

}  // namespace
}  // namespace armfarm
