// The typed configuration path: the one parser, its printing, and the relations between paths.
#include "base/config_path.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace armfarm {
namespace {

TEST(ConfigPath, ParsesKeysAndIndicesIntoSegments) {
  const ConfigPath path = parse_config_path("control.kp[1]");
  ASSERT_EQ(path.size(), 3u);
  EXPECT_EQ(path[0], (PathSegment{"control", std::nullopt}));
  EXPECT_EQ(path[1], (PathSegment{"kp", std::nullopt}));
  EXPECT_EQ(path[2], (PathSegment{"", 1u}));
  const ConfigPath nested = parse_config_path("trajectory.waypoints[2][0].x");
  ASSERT_EQ(nested.size(), 5u);
  EXPECT_EQ(nested[2].index, 2u);
  EXPECT_EQ(nested[3].index, 0u);
  EXPECT_EQ(nested[4].key, "x");
}

TEST(ConfigPath, PrintsWhatItParsedAndPrefixesOfIt) {
  for (const char* text : {"seed", "learning.lwpr.init_D", "control.kp[1]", "a[0][2].b", "a[10].b[3]"}) {
    EXPECT_EQ(parse_config_path(text).to_string(), text);
  }
  const ConfigPath path = parse_config_path("a[0][2].b");
  EXPECT_EQ(path.to_string(0), "");
  EXPECT_EQ(path.to_string(2), "a[0]");
  EXPECT_EQ(path.prefix(3).to_string(), "a[0][2]");
  EXPECT_EQ(ConfigPath().child("control").child("kp").element(3).to_string(), "control.kp[3]");
}

TEST(ConfigPath, RefusesMalformedTextSayingWhatIsWrong) {
  for (const char* bad : {"", "a..b", "a.", "a[x]", "[0]", "a[1", "a[]", "a[-1]", ".a"}) {
    EXPECT_THROW(parse_config_path(bad), std::invalid_argument) << bad;
  }
  try {
    parse_config_path("kp[99999999999999999999999999]");
    FAIL() << "an index past size_t parsed";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("too large"), std::string::npos) << error.what();
  }
}

TEST(ConfigPath, KnowsWhichPathsLieWithinOthers) {
  const ConfigPath control = parse_config_path("control");
  const ConfigPath kp1 = parse_config_path("control.kp[1]");
  EXPECT_TRUE(kp1.is_within(control));
  EXPECT_FALSE(control.is_within(kp1));
  EXPECT_TRUE(control.overlaps(kp1));
  EXPECT_TRUE(kp1.overlaps(control));
  EXPECT_FALSE(kp1.overlaps(parse_config_path("control.kp[0]")));
  EXPECT_FALSE(parse_config_path("control.kp").overlaps(parse_config_path("control.kd")));
  // A key named like an index is not the index.
  EXPECT_NE(parse_config_path("a.b"), parse_config_path("a[0]"));
}

}  // namespace
}  // namespace armfarm
