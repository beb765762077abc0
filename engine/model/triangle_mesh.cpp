#include "engine/model/triangle_mesh.hpp"

#include "engine/io/input_file.hpp"
#include "engine/io/number_text.hpp"
#include "engine/model/model_loading.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

namespace armfarm {
namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw ModelError(path + ":" + std::to_string(line) + ": " + what);
}

// The OBJ statements armfarm knows by name: those it reads or skips, and the rest of the
// format's keywords (free-form geometry, display attributes), which it refuses by name.
bool is_obj_keyword(const std::string& word) {
  static const char* const kKeywords[] = {"v", "vt", "vn", "vp", "f", "g", "o", "s", "usemtl", "mtllib", "l", "p",
                                          "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim",
                                          "hole", "scrv", "sp", "end", "con", "mg", "bevel", "c_interp", "d_interp",
                                          "lod", "shadow_obj", "trace_obj", "ctech", "stech", "maplib", "usemap"};
  for (const char* keyword : kKeywords) {
    if (word == keyword) return true;
  }
  return false;
}

double parse_coordinate(const std::string& token, const char* what, const std::string& path, int line) {
  const std::optional<double> value = parse_finite_number(token);
  if (!value) fail(path, line, std::string(what) + make_bad_number_ending(token));
  return *value;
}

// Resolves a 1-based OBJ index (negative: counted back from the last) among `count` elements
// of `kind` read so far; 0-based.
int resolve_index(const std::string& text, int count, const char* kind, int corner, const std::string& path, int line) {
  const std::optional<int> index = parse_integer(text);
  const std::string where = "face corner " + std::to_string(corner);
  if (!index) fail(path, line, where + ": " + kind + " index is not an integer" + describe_token(text));
  const long resolved = *index > 0 ? static_cast<long>(*index) - 1 : static_cast<long>(count) + *index;
  if (*index == 0 || resolved < 0 || resolved >= count) {
    fail(path, line, where + " refers to " + kind + " " + std::to_string(*index) + " but only " + std::to_string(count) +
                         " " + (std::string(kind) == "vertex" ? "vertices" : std::string(kind) + "s") + " precede it");
  }
  return static_cast<int>(resolved);
}

// One face corner ("7", "7/2", "7//3", "-1/2/3"): the 0-based vertex index; the texture and
// normal indices, when given, must be integers naming elements read so far.
int parse_corner(const std::string& token, int corner, int vertex_count, int texture_count, int normal_count,
                 const std::string& path, int line) {
  std::vector<std::string> parts(1);
  for (char c : token) {
    if (c == '/') {
      parts.emplace_back();
    } else {
      parts.back() += c;
    }
  }
  if (parts.size() > 3) fail(path, line, "face corner " + std::to_string(corner) + " has more than v/vt/vn");
  const int vertex = resolve_index(parts[0], vertex_count, "vertex", corner, path, line);
  if (parts.size() >= 2 && !(parts.size() == 3 && parts[1].empty())) {
    resolve_index(parts[1], texture_count, "texture coordinate", corner, path, line);
  }
  if (parts.size() == 3) resolve_index(parts[2], normal_count, "normal", corner, path, line);
  return vertex;
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
  int texture_count = 0, normal_count = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    const std::size_t control = find_control_character(text);
    if (control != std::string::npos) {
      fail(path, line, describe_control_character(text[control]) + " at column " + std::to_string(control + 1));
    }
    std::istringstream fields(text);
    std::string keyword;
    if (!(fields >> keyword) || keyword[0] == '#') continue;
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;) tokens.push_back(token);
    if (keyword == "v") {
      // x y z, then optionally w or a colour: all finite numbers; the position is x y z.
      if (tokens.size() < 3) fail(path, line, "vertex needs three coordinates");
      for (const std::string& token : tokens) parse_coordinate(token, "vertex coordinate", path, line);
      const std::array<double, 3> xyz = {*parse_finite_number(tokens[0]), *parse_finite_number(tokens[1]),
                                         *parse_finite_number(tokens[2])};
      auto [it, inserted] = index_of_position.emplace(xyz, static_cast<int>(mesh.vertices.size()));
      if (inserted) mesh.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
      canonical.push_back(it->second);
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vp") {
      // Not part of the solid, but faces refer to them: numbers and counts are checked.
      const bool normal = keyword == "vn";
      const std::size_t lo = normal ? 3 : 1, hi = 3;
      if (tokens.size() < lo || tokens.size() > hi) {
        fail(path, line, keyword + " needs " + (normal ? std::string("three numbers") : std::string("one to three numbers")) +
                             ", got " + std::to_string(tokens.size()));
      }
      for (const std::string& token : tokens) parse_coordinate(token, (keyword + " value").c_str(), path, line);
      if (keyword == "vt") ++texture_count;
      if (normal) ++normal_count;
    } else if (keyword == "f") {
      std::vector<int> corners;
      for (std::size_t k = 0; k < tokens.size(); ++k) {
        corners.push_back(canonical[parse_corner(tokens[k], static_cast<int>(k + 1), static_cast<int>(canonical.size()),
                                                 texture_count, normal_count, path, line)]);
      }
      if (corners.size() < 3) fail(path, line, "face has fewer than three corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        mesh.triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
        mesh.triangle_lines.push_back(line);
      }
    } else if (keyword == "g" || keyword == "o" || keyword == "s" || keyword == "usemtl" || keyword == "mtllib") {
      continue;  // grouping and appearance: no bearing on the solid
    } else if (is_obj_keyword(keyword)) {
      fail(path, line, "unsupported OBJ statement '" + keyword + "' (only v and f define the solid)");
    } else {
      fail(path, line, "not an OBJ statement (only v and f define the solid; vt vn vp g o s usemtl mtllib are skipped)");
    }
  }
  if (mesh.triangles.empty()) throw ModelError(path + ": mesh has no faces");
  return mesh;
}

}  // namespace armfarm
