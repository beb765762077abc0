// Numbers as text: the general form against printf's own %g and the round trip at 17 digits, the
// table form's switch to scientific notation at its two bounds.
#include "base/number_format.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>
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

}  // namespace
}  // namespace armfarm
