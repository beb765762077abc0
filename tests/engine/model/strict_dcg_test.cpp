// Strict DCG numbers (issue 16): every number of a tag is all number, finite and decimal; an
// embedded NUL or control character, hex, NaN or Inf is refused with the file and line.
#include "engine/model/model_loading.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

// The ModelError of loading a one-box DCG whose box size tag is s(SIZE), after the file name.
std::string dcg_problem(const std::string& size) {
  const std::string path = test_support::scratch_file("strict.dcg");
  std::ofstream(path, std::ios::binary) << "<DCGraph>\nB ground <t(0 0 0)> o(1) s(1 1 0.1) fix;\nB arm <> o(1) s(" + size +
                                               ") w(1) ee(0 0 0);\nJ ground-arm <t(0 0 0.1)>;\n</DCGraph>\n";
  std::string problem = "(loaded)";
  try {
    load_arm_model(path);
  } catch (const ModelError& error) {
    problem = std::string(error.what()).substr(path.size());
  }
  std::remove(path.c_str());
  return problem;
}

TEST(StrictDcg, PlainNumbersLoad) { EXPECT_EQ(dcg_problem("0.1 0.2 0.3"), "(loaded)"); }

TEST(StrictDcg, NulInsideANumberIsRefusedNotTruncated) {
  EXPECT_EQ(dcg_problem(std::string("0.1 0.2\0" "5 0.3", 13)), ":3: tag s: value 2 is not a finite number (a 5-byte token, not shown)");
}

TEST(StrictDcg, NanInfHexAndOverflowAreRefused) {
  EXPECT_EQ(dcg_problem("0.1 nan 0.3"), ":3: tag s: value 2 is not a finite number: 'nan'");
  EXPECT_EQ(dcg_problem("0.1 0.2 -inf"), ":3: tag s: value 3 is not a finite number: '-inf'");
  EXPECT_EQ(dcg_problem("1e999 0.2 0.3"), ":3: tag s: value 1: '1e999' overflows a double (above 1.8e308 in magnitude)");
  // Out of a double's range, not "not a finite number": 1e-400 is a finite number no double holds.
  EXPECT_EQ(dcg_problem("0.1 1e-400 0.3"),
            ":3: tag s: value 2: '1e-400' underflows to zero (below 4.9e-324, the smallest double, in magnitude)");
  EXPECT_EQ(dcg_problem("0x1p-3 0.2 0.3"), ":3: tag s: value 1 is not a finite number (a 6-byte token, not shown)");
  EXPECT_EQ(dcg_problem("0.1m 0.2 0.3"), ":3: tag s: value 1 is not a finite number (a 4-byte token, not shown)");
}

}  // namespace
}  // namespace armfarm
