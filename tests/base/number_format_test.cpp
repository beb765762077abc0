// Numbers as text: the general form against printf's own %g and the round trip at 17 digits, the
// table form's switch to scientific notation at its two bounds, and the shortest form against
// strtod (it reads back) and against printf's %g with the fewest digits that read back (it is no
// longer).
#include "base/number_format.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

namespace armfarm {
namespace {

TEST(NumberFormat, SixDigitsAsAStreamPrintsThemAndSeventeenReadBackExactly) {
  for (double value : {0.0, -0.0, 0.05, 1.0 / 3.0, -1.5, 1e6, 123456.7, 1e-7, 86400.0}) {
    std::ostringstream stream;  // the engine's key table printed its ranges this way before
    stream << value;
    EXPECT_EQ(format_number(value), stream.str()) << value;
    EXPECT_EQ(std::strtod(format_number(value, 17).c_str(), nullptr), value) << value;
  }
  EXPECT_EQ(format_number(1e9), "1e+09");
  EXPECT_EQ(format_number(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
}

TEST(NumberFormat, TableCellsTurnScientificBelowAHundredthAndFromAHundredThousand) {
  EXPECT_EQ(format_table_number(1.95e-3), "1.950e-03");
  EXPECT_EQ(format_table_number(9.38e-4, 3), "9.38e-04");
  EXPECT_EQ(format_table_number(0.01), "0.01");
  EXPECT_EQ(format_table_number(0.890025), "0.89");
  EXPECT_EQ(format_table_number(99999.0), "1e+05");  // %g rounds; still below the bound
  EXPECT_EQ(format_table_number(100000.0), "1.000e+05");
  EXPECT_EQ(format_table_number(0.0), "0");
  EXPECT_EQ(format_table_number(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_table_number(-std::numeric_limits<double>::infinity()), "-inf");
}

// printf's %g text of `value` with the fewest significant digits that read back as `value`.
std::string make_fewest_digits_text(double value) {
  char text[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

TEST(NumberFormat, ShortestNumbersReadBackExactlyAndAreNoLongerThanTheFewestDigitsOfPercentG) {
  EXPECT_EQ(format_shortest_number(0.1), "0.1");
  EXPECT_EQ(format_shortest_number(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(format_shortest_number(1e-300), "1e-300");
  EXPECT_EQ(format_shortest_number(-0.0), "-0");
  EXPECT_EQ(format_shortest_number(60.0), "60");  // a Slurm script's --timeout
  EXPECT_EQ(format_shortest_number(90.5), "90.5");
  EXPECT_EQ(format_shortest_number(100.0), "100");  // %.1g would print 1e+02
  EXPECT_EQ(format_shortest_number(std::nan("")), "nan");
  EXPECT_EQ(format_shortest_number(-std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_shortest_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(format_shortest_number(-std::numeric_limits<double>::infinity()), "-inf");
  std::mt19937_64 bits(42);  // test data only
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t word = bits();
    double value;
    std::memcpy(&value, &word, sizeof value);
    if (!std::isfinite(value)) continue;
    const std::string text = format_shortest_number(value);
    ASSERT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
    // No longer than %g with the fewest digits (to_chars also takes the shorter of the fixed
    // and the scientific forms: "100", not "1e+02").
    ASSERT_LE(text.size(), make_fewest_digits_text(value).size()) << text << " vs " << make_fewest_digits_text(value);
  }
}

}  // namespace
}  // namespace armfarm
