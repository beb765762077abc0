// parse_json_document: the same values as nlohmann's parser, the position of every value under
// the path spec errors use, and overflowing numbers refused with line, column and path.
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(JsonDocument, ValuesMatchTheDomParserAndPositionsAreRecorded) {
  const std::string text = "{\"a\": [1, [2.5, \"x\"], {\"b.c\": null}],\n \"d\": true}";
  const JsonDocument document = parse_json_document(text, "t.json");
  EXPECT_EQ(document.value, nlohmann::json::parse(text));
  EXPECT_EQ(document.describe_position("a"), "line 1, column 7");
  EXPECT_EQ(document.describe_position("a[1][0]"), "line 1, column 12");
  EXPECT_EQ(document.describe_position("a[1][1]"), "line 1, column 17");
  EXPECT_EQ(document.describe_position("a[2][\"b.c\"]"), "line 1, column 31");
  EXPECT_EQ(document.describe_position("d"), "line 2, column 7");
  EXPECT_EQ(document.describe_position("e"), "");
}

TEST(JsonDocument, OverflowNamesLineColumnAndPath) {
  try {
    parse_json_document("{\"x\": {\"y\": [0,\n -2e308]}}", "t.json");
    FAIL() << "accepted -2e308";
  } catch (const SpecError& error) {
    EXPECT_EQ(error.lines().at(0), "t.json: line 2, column 2: x.y[1]: the number -2e308 does not fit a double (JSON numbers here must be finite)");
  }
}

TEST(JsonDocument, NonFiniteSpellings) {
  for (const char* text : {"NaN", "nan", "-inf", "+Infinity", "INF"}) EXPECT_TRUE(is_non_finite_number_text(text)) << text;
  for (const char* text : {"none", "info", "", "1e309"}) EXPECT_FALSE(is_non_finite_number_text(text)) << text;
}

}  // namespace
}  // namespace armfarm
