#pragma once
// What the URDF and DCG loaders share: reading the model file's text (the one place a loader
// reads its source file) and putting the joints in tree order.
#include <string>
#include <utility>
#include <vector>

namespace armfarm {

/// The whole text of the model file at `path`, read as a confined input (engine/io/input_file.hpp:
/// a regular file under the arm-model size cap). Throws ModelError with the one-line reason.
std::string read_model_file(const std::string& path);

/// A joint as the tree ordering sees it: indices of its parent and child links.
struct TreeEdge {
  int parent_link = -1;
  int child_link = -1;
};

/// Tree order of `joints` (indices into it): depth first from each of `roots` in turn, a
/// link's child joints in the order they appear in `joints`. Joints not reachable from the
/// roots are left out (the caller reports them: cycles, disconnected links).
std::vector<int> calc_tree_order(const std::vector<TreeEdge>& joints, const std::vector<int>& roots);

}  // namespace armfarm
