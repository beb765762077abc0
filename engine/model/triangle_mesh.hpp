#pragma once
// A closed triangle mesh read from a Wavefront OBJ file (only `v` and `f` matter; texture
// coordinates, normals, groups and materials are skipped). Units: whatever the file uses,
// taken as metres. Frame: the body frame of the DCG body that names the file.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace armfarm {

/// Vertices and triangles of a mesh. Faces with more than three corners are fan-triangulated;
/// vertices at exactly the same position are merged so that a closed surface written with
/// duplicated vertices still reads as closed. `triangle_lines[i]` is the 1-based line of the
/// `f` statement triangle i came from (for messages).
struct TriangleMesh {
  std::string source_file;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;  ///< indices into vertices, counter-clockwise seen from outside
  std::vector<int> triangle_lines;
};

/// Reads a Wavefront OBJ file: `v x y z [w]`, `f a b c ...` with `a`, `a/t`, `a//n`, `a/t/n`
/// corners and negative (relative) indices. Throws ModelError `<file>:<line>: <what>` on a
/// missing file, malformed number, index out of range, face with fewer than three corners,
/// or an unsupported statement.
TriangleMesh load_obj_mesh(const std::string& path);

}  // namespace armfarm
