// Spec validation: a corpus of bad specs (tests/data/specs/bad), each giving one-line errors
// that name the file and the JSON path; includes merge in order.
#include "runner/execution/fake_job.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_spec.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <fstream>

namespace armfarm {
namespace {

const std::string kSpecs = std::string(ARMFARM_TEST_DATA_DIR) + "/specs/";

struct BadSpec {
  const char* file;
  const char* expected;  // the JSON path and message that must appear in one error line
};

const BadSpec kBadSpecs[] = {
    {"unknown_top_key", "sweeep: unknown key (did you mean 'sweep'?)"},
    {"missing_name", "name: missing"},
    {"unknown_config_key", "base.control.gain_scal: unknown key (did you mean 'gain_scale'?)"},
    {"wrong_type", "base.control.kp: expected an array, got \"high\""},
    {"wrong_type_element", "base.control.kp[1]: expected a number, got \"x\""},
    {"path_names_nothing", "sweep.grid[\"learning.lwpr.initD\"]: 'learning.lwpr.initD' names nothing in the job "
                           "configuration: no key 'initD' in 'learning.lwpr' (did you mean 'init_D'?)"},
    {"index_out_of_range", "sweep.grid[\"control.kp[5]\"]: 'control.kp[5]' names nothing in the job configuration: "
                           "index 5 is out of range"},
    {"axis_wrong_type", "sweep.grid[\"trajectory.kind\"][0]: expected a string, got 1"},
    {"out_of_range_value", "sweep.grid[\"control.gain_scale\"][1]: control.gain_scale: must be positive"},
    {"zip_lengths", "sweep.zip[0]: lists that vary together must have the same length"},
    {"random_bad_bounds", "sweep.random.params[\"learning.lwpr.init_D\"].loguniform: loguniform needs 0 < low"},
    {"random_unknown_distribution", "sweep.random.params[\"learning.lwpr.init_D\"].normal: unknown distribution"},
    {"repeat_zero", "sweep.repeat: expected a number of repeats"},
    {"not_json", "line 2, column 13: not valid JSON"},
    {"overlapping_axes", "overlaps 'control.kp'"},
    {"base_out_of_range", "base.simulation.samples: must be in [1, 1000000]"},
    {"include_bad", "bad_include_config.json: control.kq: unknown key (did you mean 'kd'?)"},
    {"unknown_sweep_key", "sweep.gird: unknown key (did you mean 'grid'?)"},
    {"integer_expected", "base.simulation.samples: expected an integer, got 2.5"},
};

// Loading and expanding is what `armfarm run` does before touching a database.
std::vector<std::string> collect_errors(const std::string& path) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  try {
    expand_sweep(load_sweep_spec(path, schema), schema);
  } catch (const SpecError& e) {
    return e.lines();
  }
  return {};
}

TEST(SweepSpec, EveryBadSpecIsRejectedWithFileAndJsonPath) {
  for (const BadSpec& bad : kBadSpecs) {
    const std::string path = kSpecs + "bad/" + bad.file + ".json";
    const std::vector<std::string> errors = collect_errors(path);
    ASSERT_FALSE(errors.empty()) << bad.file << " was accepted";
    bool found = false;
    for (const std::string& line : errors) {
      EXPECT_EQ(line.find('\n'), std::string::npos);
      EXPECT_NE(line.find(".json: "), std::string::npos) << line;
      if (line.find(bad.expected) != std::string::npos) found = true;
    }
    EXPECT_TRUE(found) << bad.file << ": expected \"" << bad.expected << "\" in:\n" << errors.front();
  }
}

TEST(SweepSpec, ErrorsNameTheSpecFile) {
  const auto errors = collect_errors(kSpecs + "bad/wrong_type.json");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind(kSpecs + "bad/wrong_type.json: ", 0), 0u) << errors[0];
  EXPECT_NE(collect_errors(kSpecs + "bad/no_such_file.json").at(0).find("no such file"), std::string::npos);
}

TEST(SweepSpec, IncludesMergeInOrderAndBaseOverridesThem) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  const SweepSpec spec = load_sweep_spec(kSpecs + "fake_include.json", schema);
  EXPECT_EQ(spec.base["control"]["kp"], nlohmann::json({10.0, 20.0}));     // from the first include
  EXPECT_EQ(spec.base["control"]["gain_scale"], 3.0);                      // the second overrides the first
  EXPECT_EQ(spec.base["simulation"]["samples"], 50);
  EXPECT_EQ(spec.base["trajectory"]["kind"], "circle");
  EXPECT_EQ(spec.base["trajectory"]["period"], 1.5);                       // base
  EXPECT_EQ(spec.base["control"]["kd"], schema.defaults["control"]["kd"]);  // defaults elsewhere
  ASSERT_EQ(spec.grid.size(), 1u);
  EXPECT_TRUE(spec.base["control"]["gain_scale"].is_number_float());
}

TEST(SweepSpec, IntegersGivenForRealsAreNormalized) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  const SweepSpec spec =
      parse_sweep_spec(R"({"name": "n", "base": {"control": {"gain_scale": 2}}})", "inline.json", ".", schema);
  EXPECT_TRUE(spec.base["control"]["gain_scale"].is_number_float());
  EXPECT_EQ(spec.base["control"]["gain_scale"].get<double>(), 2.0);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/spec/spec_input_files_test.cpp:
// Spec files and includes go through the confined reader: /dev/zero, a FIFO, a directory or an
// oversized include is refused at once with the including spec and the path named, and a file
// that is not JSON is refused without its content in the message.

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
