// Dotted paths: parsing, lookup with suggestions, assignment.
#include "runner/spec/config_path.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(ConfigPath, ParsesKeysAndIndices) {
  const auto segments = parse_config_path("control.kp[1]");
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[1].key, "kp");
  EXPECT_EQ(segments[2].index, 1u);
  EXPECT_EQ(make_config_path(segments), "control.kp[1]");
  EXPECT_EQ(make_config_path(parse_config_path("a[0][2].b")), "a[0][2].b");
  for (const char* bad : {"", "a..b", "a.", "a[x]", "[0]", "a[1"}) {
    EXPECT_THROW(parse_config_path(bad), std::invalid_argument) << bad;
  }
}

TEST(ConfigPath, FindsAndSetsElementsAndExplainsMisses) {
  nlohmann::json config = {{"control", {{"kp", {1.0, 2.0}}, {"gain_scale", 1.0}}}};
  std::string problem;
  EXPECT_EQ(*find_config_element(config, parse_config_path("control.kp[1]"), problem), 2.0);
  EXPECT_EQ(find_config_element(config, parse_config_path("control.kp[2]"), problem), nullptr);
  EXPECT_NE(problem.find("out of range"), std::string::npos);
  EXPECT_EQ(find_config_element(config, parse_config_path("control.gain_scal"), problem), nullptr);
  EXPECT_NE(problem.find("did you mean 'gain_scale'"), std::string::npos) << problem;
  set_config_element(config, parse_config_path("control.kp[0]"), 7.0);
  EXPECT_EQ(config["control"]["kp"][0], 7.0);
}

}  // namespace
}  // namespace armfarm
