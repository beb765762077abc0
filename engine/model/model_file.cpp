#include "engine/model/model_file.hpp"

#include "engine/io/input_file.hpp"
#include "engine/model/model_loading.hpp"

#include <functional>
#include <map>
#include <set>

namespace armfarm {

std::string read_model_file(const std::string& path) { return read_input_file_as<ModelError>(path, InputFileKind::arm_model); }

std::vector<int> calc_tree_order(const std::vector<TreeEdge>& joints, const std::vector<int>& roots) {
  std::map<int, std::vector<int>> children;  // parent link -> joint indices, in input order
  for (int j = 0; j < static_cast<int>(joints.size()); ++j) children[joints[j].parent_link].push_back(j);
  std::vector<int> order;
  std::set<int> visited;  // links; guards against cycles
  std::function<void(int)> descend = [&](int link) {
    if (!visited.insert(link).second) return;
    for (int j : children[link]) {
      if (visited.count(joints[j].child_link) != 0) continue;
      order.push_back(j);
      descend(joints[j].child_link);
    }
  };
  for (int root : roots) descend(root);
  return order;
}

}  // namespace armfarm
