// parse_json_document: the same values as nlohmann's parser, the position of every value under
// the path spec errors use, and overflowing numbers refused with line, column and path.
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

// Issue 30 case 7: 10^5 levels grew memory by 40 MB/s. Refused at the 257th bracket, whose
// column the message names: the reader stopped there and never read the rest.
TEST(JsonDocument, NestingDeeperThanTheCapIsRefusedWhereItCrossesTheCap) {
  const std::string text = std::string(100000, '[') + std::string(100000, ']');
  try {
    parse_json_document(text, "deep.json");
    FAIL() << "accepted 100000 levels";
  } catch (const SpecError& error) {
    ASSERT_EQ(error.lines().size(), 1u);
    EXPECT_EQ(error.lines()[0], "deep.json: line 1, column 257: arrays and objects nest deeper than 256 levels (the most a spec may nest)");
  }
  // 256 levels are read.
  const std::string ok = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_EQ(parse_json_document(ok, "ok.json").value, nlohmann::json::parse(ok));
}

// Positions are stored per segment, not per whole path: a 10 kB key above 2000 values costs
// the key once, and a value's position is still found by its whole path.
TEST(JsonDocument, PositionStorageIsLinearInTheDocument) {
  const std::string key(10000, 'k');
  std::string text = "{\"" + key + "\": [";
  for (int i = 0; i < 2000; ++i) text += (i ? ",[1]" : "[1]");
  text += "]}";
  const JsonDocument document = parse_json_document(text, "long.json");
  std::size_t stored = 0;
  for (const JsonDocument::Node& node : document.nodes) stored += node.segment.size();
  EXPECT_LT(stored, text.size());
  EXPECT_EQ(document.nodes.size(), 2u + 2000u * 2u);
  EXPECT_EQ(document.describe_position(key + "[1999][0]"), "line 1, column " + std::to_string(text.size() - 3));
  EXPECT_EQ(document.describe_position(key + "[2000]"), "");
}

TEST(JsonDocument, DuplicateKeysAreRefusedWithThePathOfTheSecond) {
  try {
    parse_json_document("{\"base\": {\"seed\": 1,\n \"seed\": 2}}", "dup.json");
    FAIL() << "accepted a duplicate key";
  } catch (const SpecError& error) {
    EXPECT_EQ(error.lines().at(0), "dup.json: line 2, column 2: base.seed: the key \"seed\" appears twice in this object (JSON keeps only one: remove the other)");
  }
  // The same key in two objects is not a duplicate.
  EXPECT_NO_THROW(parse_json_document("{\"a\": {\"x\": 1}, \"b\": {\"x\": 1}}", "t.json"));
}

TEST(JsonDocument, ControlCharactersInStringsAndKeysAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      {"{\"name\": \"a\\u0000b\"}", "t.json: line 1, column 10: name: the string holds the control character U+0000 (names and values must be printable text)"},
      {"{\"name\": \"\\u001b[31mred\"}", "t.json: line 1, column 10: name: the string holds the control character U+001B (names and values must be printable text)"},
      {"{\"a\\nb\": 1}", "t.json: line 1, column 2: [\"a\\nb\"]: the key holds the control character U+000A (names and values must be printable text)"},
      {"[\"x\", \"\\u007f\"]", "t.json: line 1, column 7: [1]: the string holds the control character U+007F (names and values must be printable text)"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_json_document(text, "t.json");
      ADD_FAILURE() << "accepted " << text;
    } catch (const SpecError& error) {
      EXPECT_EQ(error.lines().at(0), expected) << text;
    }
  }
  // Printable UTF-8 is fine.
  EXPECT_NO_THROW(parse_json_document("{\"name\": \"Gen3 \u00e9\u2192\"}", "t.json"));
}

TEST(JsonDocument, NonFiniteSpellings) {
  for (const char* text : {"NaN", "nan", "-inf", "+Infinity", "INF"}) EXPECT_TRUE(is_non_finite_number_text(text)) << text;
  for (const char* text : {"none", "info", "", "1e309"}) EXPECT_FALSE(is_non_finite_number_text(text)) << text;
}

}  // namespace
}  // namespace armfarm
