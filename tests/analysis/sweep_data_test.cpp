// analysis/sweep_data: a job's parameters as the tables and comparisons read them.
#include "analysis/sweep_data.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace armfarm {
namespace {

std::vector<std::string> list_texts(const nlohmann::json& config) {
  std::vector<std::string> texts;
  for (const ConfigPath& path : list_config_leaf_paths(config)) texts.push_back(path.to_string());
  return texts;
}

TEST(SweepData, LeafPathsGoDownObjectsOnly) {
  const nlohmann::json config = nlohmann::json::parse(R"({"seed": 3, "control": {"kp": [1, 2], "gains": {}},
      "learning": {"lwpr": {"init_D": [[1, 0], [0, 1]]}, "mode": "online"}})");
  // Key order (nlohmann's objects are sorted); arrays are one value; an empty object has none.
  EXPECT_EQ(list_texts(config), (std::vector<std::string>{"control.kp", "learning.lwpr.init_D", "learning.mode", "seed"}));
  // Each is a path find_param_value reads back.
  JobResult job;
  job.config = config;
  EXPECT_EQ(find_param_value(job, "learning.mode"), "online");
  EXPECT_EQ(find_param_value(job, "control.kp[1]"), 2);
  EXPECT_TRUE(list_config_leaf_paths(nlohmann::json()).empty());
  EXPECT_TRUE(list_config_leaf_paths(nlohmann::json(4)).empty());
}

TEST(SweepData, AKeyWithADotIsOneSegment) {
  const std::vector<ConfigPath> paths = list_config_leaf_paths(nlohmann::json::parse(R"({"a.b": {"c": 1}})"));
  ASSERT_EQ(paths.size(), 1u);
  ASSERT_EQ(paths[0].size(), 2u);
  EXPECT_EQ(paths[0][0].key, "a.b");
  EXPECT_EQ(paths[0][1].key, "c");
}

}  // namespace
}  // namespace armfarm
