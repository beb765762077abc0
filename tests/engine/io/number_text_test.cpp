// Strict number tokens: the whole token is a plain decimal number, finite and in range.
#include "engine/io/number_text.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

namespace armfarm {
namespace {

TEST(NumberText, AcceptsPlainDecimalNumbers) {
  EXPECT_EQ(parse_finite_number("0.33801"), 0.33801);
  EXPECT_EQ(parse_finite_number("-1e-3"), -1e-3);
  EXPECT_EQ(parse_finite_number("+2.5E2"), 250.0);
  EXPECT_EQ(parse_finite_number(".5"), 0.5);
  EXPECT_EQ(parse_finite_number("5."), 5.0);
  EXPECT_EQ(parse_finite_number("1.7976931348623157e308"), std::numeric_limits<double>::max());
}

TEST(NumberText, RefusesEverythingElse) {
  const std::vector<std::string> bads = {"", "nan", "NaN", "inf", "-inf", "Infinity", "1e999", "-1e999", "0x1p3",
                                        "1.2.3", "1e", "e5", ".", "-", "+", "1,5", " 1", "1 ", "1\r",
                                        std::string("0.33801\0" "5", 9), "1\x01", "12abc", "--1", "1e+-2"};
  for (const std::string& bad : bads) {
    EXPECT_FALSE(parse_finite_number(bad).has_value()) << "accepted '" << bad << "'";
  }
}

TEST(NumberText, IntegersAreWholeAndInRange) {
  EXPECT_EQ(parse_integer("7"), 7);
  EXPECT_EQ(parse_integer("-8"), -8);
  EXPECT_EQ(parse_integer("+3"), 3);
  for (const char* bad : {"", "-", "1.0", "1e2", "nan", "7x", "99999999999", " 1"}) {
    EXPECT_FALSE(parse_integer(bad).has_value()) << "accepted '" << bad << "'";
  }
}

TEST(NumberText, MessagesQuoteOnlyNumberLikeTokens) {
  EXPECT_EQ(describe_token("1e999"), ": '1e999'");
  EXPECT_EQ(describe_token("-inf"), ": '-inf'");
  EXPECT_EQ(describe_token("root:x:0:0:root:/root:/bin/bash"), " (a 31-byte token, not shown)");
  EXPECT_EQ(describe_token("password"), " (a 8-byte token, not shown)");
  EXPECT_EQ(describe_token(std::string("0.3\0" "5", 5)), " (a 5-byte token, not shown)");
  EXPECT_EQ(describe_token(""), " (empty)");
}

TEST(NumberText, ControlCharactersAreFoundAndNamed) {
  EXPECT_EQ(find_control_character("a\tb"), std::string_view::npos);
  EXPECT_EQ(find_control_character(std::string("0.33801\0" "5", 9)), 7u);
  EXPECT_EQ(find_control_character("1\r2"), 1u);
  EXPECT_EQ(describe_control_character('\0'), "NUL");
  EXPECT_EQ(describe_control_character('\r'), "CR");
  EXPECT_EQ(describe_control_character('\x1b'), "control character 0x1b");
  EXPECT_EQ(describe_control_character('\x7f'), "control character 0x7f");
}

}  // namespace
}  // namespace armfarm
