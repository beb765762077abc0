#include "engine/model/model_file.hpp"

#include "engine/io/input_file.hpp"
#include "engine/model/model_loading.hpp"

#include <algorithm>

namespace armfarm {

std::string read_model_file(const std::string& path) { return read_input_file_as<ModelError>(path, InputFileKind::arm_model); }

std::vector<int> calc_tree_order(const std::vector<TreeEdge>& joints, const std::vector<int>& roots) {
  // Linear in the number of joints: children lists indexed by link, an explicit stack (a chain
  // of a thousand links would otherwise recurse a thousand frames deep).
  int n_links = 0;
  for (const TreeEdge& edge : joints) n_links = std::max({n_links, edge.parent_link + 1, edge.child_link + 1});
  for (const int root : roots) n_links = std::max(n_links, root + 1);
  std::vector<std::vector<int>> children(static_cast<std::size_t>(n_links));  // parent link -> joints, input order
  for (int j = 0; j < static_cast<int>(joints.size()); ++j) {
    if (joints[j].parent_link >= 0) children[joints[j].parent_link].push_back(j);
  }
  std::vector<int> order;
  std::vector<bool> visited(static_cast<std::size_t>(n_links), false);  // links; guards against cycles
  struct Frame {
    int link;
    std::size_t next_child;
  };
  std::vector<Frame> stack;
  for (const int root : roots) {
    if (root < 0 || visited[root]) continue;
    visited[root] = true;
    stack.push_back({root, 0});
    while (!stack.empty()) {
      Frame& top = stack.back();
      if (top.next_child == children[top.link].size()) {
        stack.pop_back();
        continue;
      }
      const int j = children[top.link][top.next_child++];
      const int child = joints[j].child_link;
      if (child < 0 || visited[child]) continue;
      visited[child] = true;
      order.push_back(j);
      stack.push_back({child, 0});
    }
  }
  return order;
}

}  // namespace armfarm
