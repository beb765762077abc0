// CSV reader: values and header, file:line errors for malformed rows.
#include "runner/io/csv_reader.hpp"

#include <gtest/gtest.h>

#include "support/command_line.hpp"
#include "support/scratch_file.hpp"
#include "support/text_file.hpp"

#include <filesystem>
#include <fstream>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace armfarm::io {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = test_support::scratch_file("csv_" + name);
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& path) {
  try {
    load_csv(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(CsvReader, ReadsHeaderAndValues) {
  const CsvTable t = load_csv(write_temp("ok.csv", "a, b,c\n1,2.5,-3e2\r\n\n4,5,6\n"));
  EXPECT_EQ(t.header, (std::vector<std::string>{"a", "b", "c"}));
  ASSERT_EQ(t.values.rows(), 2);
  EXPECT_EQ(t.values(0, 2), -300.0);
  EXPECT_EQ(t.values(1, 1), 5.0);
}

TEST(CsvReader, ErrorsNameFileAndLine) {
  const std::string short_row = write_temp("short.csv", "a,b\n1,2\n3\n");
  EXPECT_EQ(error_of(short_row), short_row + ":3: 1 fields, expected 2");
  const std::string text = write_temp("text.csv", "a,b\n1,x\n");
  EXPECT_EQ(error_of(text), text + ":2: column 'b': not a finite number (a 1-byte token, not shown)");
  const std::string nan = write_temp("nan.csv", "a\nnan\n");
  EXPECT_NE(error_of(nan).find(":2:"), std::string::npos);
  EXPECT_NE(error_of(write_temp("empty.csv", "")).find("empty file"), std::string::npos);
  EXPECT_EQ(error_of("/no/such/file.csv"), "/no/such/file.csv: no such file");
}

}  // namespace
}  // namespace armfarm::io

// ------------------------------------------------------------------------------------------------
// Folded in from runner/io/strict_csv_test.cpp:
// Strict CSV reading (issue 16): a field is a number only if all of it is one; NUL, CR and
// other control characters, NaN and Inf are refused with the file and line, and messages do not
// quote a file that is not a CSV.

namespace armfarm::io {
namespace {

// The error of reading `bytes` as a CSV file, after the file name; "(read)" if it reads.
std::string csv_problem(const std::string& bytes) {
  const std::string path = test_support::scratch_file("strict.csv");
  std::ofstream(path, std::ios::binary) << bytes;
  std::string problem = "(read)";
  try {
    load_csv(path);
  } catch (const std::runtime_error& error) {
    problem = std::string(error.what()).substr(path.size());
  }
  std::remove(path.c_str());
  return problem;
}

TEST(StrictCsv, NulInsideANumberIsRefusedNotTruncated) {
  // The case: "0.33801\x005" used to read as 0.33801.
  EXPECT_EQ(csv_problem(std::string("t,q1\n0,0.33801\0" "5\n", 17)), ":2: NUL in field 2 (byte 10 of the line)");
}

TEST(StrictCsv, CrInsideANumberIsRefusedButCrlfLineEndsRead) {
  EXPECT_EQ(csv_problem("t,q1\n0,0.33\r5\n"), ":2: CR in field 2 (byte 7 of the line)");
  EXPECT_EQ(csv_problem("t,q1\r\n0,0.335\r\n"), "(read)");
}

TEST(StrictCsv, OtherControlCharactersAreRefusedAnywhere) {
  EXPECT_EQ(csv_problem("t,q\x1b[31m1\n0,1\n"), ":1: control character 0x1b in field 2 (byte 4 of the line)");
  EXPECT_EQ(csv_problem("t,q1\n0,1\x7f\n"), ":2: control character 0x7f in field 2 (byte 4 of the line)");
  EXPECT_EQ(csv_problem("t,q1\n\t0 , 1\t\n"), "(read)");  // tabs and spaces around fields are fine
}

TEST(StrictCsv, NanInfHexAndTrailingGarbageAreRefused) {
  EXPECT_EQ(csv_problem("t,q1\n0,nan\n"), ":2: column 'q1': not a finite number: 'nan'");
  EXPECT_EQ(csv_problem("t,q1\n0,-inf\n"), ":2: column 'q1': not a finite number: '-inf'");
  EXPECT_EQ(csv_problem("t,q1\n0,1e999\n"), ":2: column 'q1': '1e999' overflows a double (above 1.8e308 in magnitude)");
  EXPECT_EQ(csv_problem("t,q1\n0,0x1p3\n"), ":2: column 'q1': not a finite number (a 5-byte token, not shown)");
  EXPECT_EQ(csv_problem("t,q1\n0,1.5rad\n"), ":2: column 'q1': not a finite number (a 6-byte token, not shown)");
  EXPECT_EQ(csv_problem("t,q1\n0,\n"), ":2: column 'q1': not a finite number (empty)");
}

TEST(StrictCsv, AFileThatIsNotACsvIsNotQuoted) {
  const std::string problem = csv_problem("root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n");
  EXPECT_EQ(problem, ":2: column 1: not a finite number (a 47-byte token, not shown)");
}

TEST(StrictCsv, RowsRememberTheirFileLines) {
  const std::string path = test_support::scratch_file("lines.csv");
  std::ofstream(path, std::ios::binary) << "a\n1\n\n2\n";
  const CsvTable table = load_csv(path);
  std::remove(path.c_str());
  EXPECT_EQ(table.lines, (std::vector<int>{2, 4}));
}

}  // namespace
}  // namespace armfarm::io

// ------------------------------------------------------------------------------------------------
// Folded in from runner/io/recordings_test.cpp:
// The synthetic recordings of sweeps/thesis/data (stand-ins for the thesis's tracker recordings,
// section 6.2.3) read through the recorded-trajectory CSV path: shape, sample count, the stated
// noise level, every point inside the thesis's reaching box; and the generator reproduces them.

namespace armfarm::io {
namespace {

const std::string kDataDir = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/data/";

struct Recording {
  const char* file;
  Eigen::Index samples;  ///< rows at 100 Hz (sweeps/thesis/data/README.md)
};

const Recording kRecordings[] = {{"picking_synthetic.csv", 1133}, {"sphere_synthetic.csv", 1651}};

constexpr double kNoiseSigma = 0.0005;  // m per axis, as the README and the generator state


TEST(SyntheticRecordings, LoadAsTaskSpaceSamplesInsideTheReachingBox) {
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const CsvTable table = load_csv(kDataDir + recording.file);
    EXPECT_EQ(table.header, (std::vector<std::string>{"x", "y", "z"}));
    ASSERT_EQ(table.values.cols(), 3);
    EXPECT_EQ(table.values.rows(), recording.samples);
    // Section 6.2.2: 20 cm < x < 70 cm, 20 cm < y < 70 cm, 0 cm < z < 50 cm.
    const Eigen::Vector3d low(0.20, 0.20, 0.00), high(0.70, 0.70, 0.50);
    for (Eigen::Index k = 0; k < table.values.rows(); ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        ASSERT_GE(table.values(k, axis), low[axis]) << "sample " << k << " axis " << axis;
        ASSERT_LE(table.values(k, axis), high[axis]) << "sample " << k << " axis " << axis;
      }
    }
  }
}

TEST(SyntheticRecordings, NoiseIsTheStatedLevel) {
  // The second difference of white noise of σ has variance 6σ²; at 100 Hz the smooth motion's
  // own second difference (a·dt², below 0.3 mm) adds well under 1 % to that.
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const Eigen::MatrixXd x = load_csv(kDataDir + recording.file).values;
    const Eigen::Index n = x.rows();
    const Eigen::MatrixXd second = x.bottomRows(n - 2) - 2.0 * x.middleRows(1, n - 2) + x.topRows(n - 2);
    // Pooled over the axes (about 3400 values: the estimate's spread is about 2 %), and per axis
    // (about 1100 values) more loosely.
    const double pooled = std::sqrt(second.squaredNorm() / (6.0 * 3.0 * static_cast<double>(n - 2)));
    EXPECT_NEAR(pooled, kNoiseSigma, 0.06 * kNoiseSigma);
    for (int axis = 0; axis < 3; ++axis) {
      const double sigma = std::sqrt(second.col(axis).squaredNorm() / (6.0 * static_cast<double>(n - 2)));
      EXPECT_NEAR(sigma, kNoiseSigma, 0.15 * kNoiseSigma) << "axis " << axis;
    }
    // And the motion itself is much larger than the noise: the recording moves.
    const Eigen::RowVector3d range = x.colwise().maxCoeff() - x.colwise().minCoeff();
    EXPECT_GT(range.maxCoeff(), 0.15);
  }
}

TEST(SyntheticRecordings, GeneratorReproducesTheCommittedFiles) {
  if (std::system("command -v python3 > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 not found: cannot rerun sweeps/thesis/tools/make_recordings.py";
  }
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("armfarm-recordings-test-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const std::string command = "python3 " + std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/tools/make_recordings.py " +
                              dir.string();
  const test_support::CommandResult generated = test_support::run_command_line(command);
  ASSERT_EQ(generated.exit_code, 0) << command << "\n" << generated.output;
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const std::string fresh = test_support::read_text_file((dir / recording.file).string());
    ASSERT_FALSE(fresh.empty());
    EXPECT_TRUE(fresh == test_support::read_text_file(kDataDir + recording.file)) << "the committed file differs from the generator's output";
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace armfarm::io
