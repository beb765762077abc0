// Lookups of typed paths in a JSON tree, with suggestions, and assignment (parsing and printing:
// tests/base/config_path_test.cpp).
#include "runner/spec/config_path.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(ConfigPathLookup, FindsAndSetsElementsAndExplainsMisses) {
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
