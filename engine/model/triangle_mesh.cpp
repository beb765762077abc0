#include "engine/model/triangle_mesh.hpp"

#include "engine/io/input_file.hpp"
#include "engine/model/model_loading.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace armfarm {
namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw ModelError(path + ":" + std::to_string(line) + ": " + what);
}

double parse_coordinate(const std::string& token, const std::string& path, int line) {
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
    fail(path, line, "vertex coordinate '" + token + "' is not a finite number");
  }
  return value;
}

// Resolves one face corner ("7", "7/2", "7//3", "-1/2/3") to a 0-based index into the
// vertices read so far (OBJ indices are 1-based; negative ones count back from the last).
int parse_corner(const std::string& token, int vertex_count, const std::string& path, int line) {
  const std::string index_text = token.substr(0, token.find('/'));
  char* end = nullptr;
  errno = 0;
  const long index = std::strtol(index_text.c_str(), &end, 10);
  if (index_text.empty() || *end != '\0' || errno == ERANGE) {
    fail(path, line, "face corner '" + token + "' is not a vertex index");
  }
  long resolved = index > 0 ? index - 1 : vertex_count + index;
  if (index == 0 || resolved < 0 || resolved >= vertex_count) {
    fail(path, line, "face corner '" + token + "' refers to vertex " + std::to_string(index) +
                         " but only " + std::to_string(vertex_count) + " vertices precede it");
  }
  return static_cast<int>(resolved);
}

}  // namespace

TriangleMesh load_obj_mesh(const std::string& path) {
  std::istringstream in(read_input_file_as<ModelError>(path, InputFileKind::mesh));

  TriangleMesh mesh;
  mesh.source_file = path;
  std::vector<int> canonical;  // file vertex index -> merged vertex index
  std::map<std::array<double, 3>, int> index_of_position;

  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream fields(text);
    std::string keyword;
    if (!(fields >> keyword) || keyword[0] == '#') continue;
    if (keyword == "v") {
      std::array<double, 3> xyz{};
      std::string token;
      for (int k = 0; k < 3; ++k) {
        if (!(fields >> token)) fail(path, line, "vertex needs three coordinates");
        xyz[k] = parse_coordinate(token, path, line);
      }
      auto [it, inserted] = index_of_position.emplace(xyz, static_cast<int>(mesh.vertices.size()));
      if (inserted) mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
      canonical.push_back(it->second);
    } else if (keyword == "f") {
      std::vector<int> corners;
      std::string token;
      while (fields >> token) {
        corners.push_back(canonical[parse_corner(token, static_cast<int>(canonical.size()), path, line)]);
      }
      if (corners.size() < 3) fail(path, line, "face has fewer than three corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        mesh.triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
        mesh.triangle_lines.push_back(line);
      }
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vp" || keyword == "g" || keyword == "o" ||
               keyword == "s" || keyword == "usemtl" || keyword == "mtllib") {
      continue;  // appearance and grouping: no bearing on the solid
    } else {
      fail(path, line, "unsupported OBJ statement '" + keyword + "' (only v and f define the solid)");
    }
  }
  if (mesh.triangles.empty()) throw ModelError(path + ": mesh has no faces");
  return mesh;
}

}  // namespace armfarm
