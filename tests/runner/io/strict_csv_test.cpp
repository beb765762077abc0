// Strict CSV reading (issue 16): a field is a number only if all of it is one; NUL, CR and
// other control characters, NaN and Inf are refused with the file and line, and messages do not
// quote a file that is not a CSV.
#include "runner/io/csv_reader.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>
#include <string>

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
