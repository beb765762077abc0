// CSV text: numbers in their shortest round-trip form (checked by reading 20000 random doubles
// back with strtod), fields quoted per RFC 4180.
#include "runner/io/csv_writing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

namespace armfarm {
namespace {

TEST(CsvWriting, ShortestNumbersReadBackExactly) {
  EXPECT_EQ(make_shortest_number_text(0.1), "0.1");
  EXPECT_EQ(make_shortest_number_text(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(make_shortest_number_text(3.0 * 0.1 / 3.0 - 1e-17), make_shortest_number_text(3.0 * 0.1 / 3.0 - 1e-17));
  EXPECT_EQ(make_shortest_number_text(1e-300), "1e-300");
  EXPECT_EQ(make_shortest_number_text(-0.0), "-0");
  EXPECT_EQ(make_shortest_number_text(std::nan("")), "nan");
  EXPECT_EQ(make_shortest_number_text(-HUGE_VAL), "-inf");
  std::mt19937_64 bits(42);  // test data only
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t word = bits();
    double value;
    std::memcpy(&value, &word, sizeof value);
    if (!std::isfinite(value)) continue;
    const std::string text = make_shortest_number_text(value);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
    char longest[40];
    std::snprintf(longest, sizeof longest, "%.17g", value);
    EXPECT_LE(text.size(), std::string(longest).size() + 1) << text << " vs " << longest;  // +1: to_chars may add "e+"
  }
}

TEST(CsvWriting, FieldsAreQuotedPerRfc4180) {
  EXPECT_EQ(make_csv_field("plain"), "plain");
  EXPECT_EQ(make_csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(make_csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(make_csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(make_csv_field("cr\r"), "\"cr\r\"");
  EXPECT_EQ(make_csv_value_field(nlohmann::json(3)), "3");
  EXPECT_EQ(make_csv_value_field(nlohmann::json(0.25)), "0.25");
  EXPECT_EQ(make_csv_value_field(nlohmann::json::array({1, 2})), "\"[1,2]\"");
}

}  // namespace
}  // namespace armfarm
