// Reading a model file and the shared tree ordering: depth first in the order given, a cycle
// away from the root left out for the caller to report.
#include "engine/model/model_file.hpp"
#include "engine/model/model_loading.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace armfarm {
namespace {

TEST(ModelFile, TreeOrderIsDepthFirstInGivenOrder) {
  // links: 0 root, 1..5; joints given out of tree order.
  const std::vector<TreeEdge> joints = {{2, 3}, {0, 1}, {1, 2}, {0, 4}, {1, 5}};
  EXPECT_EQ(calc_tree_order(joints, {0}), (std::vector<int>{1, 2, 0, 4, 3}));
  // A cycle away from the root is left out for the caller to report.
  const std::vector<TreeEdge> cyclic = {{0, 1}, {2, 3}, {3, 2}};
  EXPECT_EQ(calc_tree_order(cyclic, {0}), (std::vector<int>{0}));
  EXPECT_THROW(read_model_file("/nonexistent/arm.urdf"), ModelError);
}

}  // namespace
}  // namespace armfarm
