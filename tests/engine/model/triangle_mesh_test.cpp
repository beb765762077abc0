// OBJ reading: corner forms, relative indices, polygon fans, merged duplicates and errors.
#include "engine/model/triangle_mesh.hpp"

#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>

namespace armfarm {
namespace {

std::string write_temporary_obj(const std::string& name, const std::string& text) {
  const std::string path = test_support::scratch_file(name);
  std::ofstream(path) << text;
  return path;
}

std::string obj_error(const std::string& name, const std::string& text) {
  const std::string path = write_temporary_obj(name, text);
  try {
    load_obj_mesh(path);
  } catch (const ModelError& error) {
    std::remove(path.c_str());
    return error.what();
  }
  std::remove(path.c_str());
  return "";
}

TEST(TriangleMesh, PolygonIsFanTriangulated) {
  const std::string path = write_temporary_obj("pentagon.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 2 0\nv 0 1 0\nf 1 2 3 4 5\n");
  const TriangleMesh mesh = load_obj_mesh(path);
  std::remove(path.c_str());
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles[2], Eigen::Vector3i(0, 3, 4));
  EXPECT_EQ(mesh.triangle_lines[2], 6);
}

TEST(TriangleMesh, DuplicateVerticesAreMergedAndRelativeIndicesResolve) {
  const TriangleMesh mesh = load_obj_mesh(test::data_path("obj/unit_cube_mixed.obj"));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  // "f -8/1/1 -5/1/1 -6/1/1 -7/1/1" after 8 vertices = f 1 4 3 2.
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 3, 2));
}

TEST(TriangleMesh, ErrorsNameFileLineAndProblem) {
  const std::string out_of_range = obj_error("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  EXPECT_NE(out_of_range.find("range.obj:4:"), std::string::npos) << out_of_range;
  EXPECT_NE(out_of_range.find("refers to vertex 7"), std::string::npos) << out_of_range;
  const std::string zero = obj_error("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_NE(zero.find("zero.obj:4:"), std::string::npos) << zero;
  const std::string nan = obj_error("nan.obj", "v 0 nan 0\n");
  EXPECT_NE(nan.find("nan.obj:1: vertex coordinate is not a finite number: 'nan'"), std::string::npos) << nan;
  const std::string two = obj_error("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_NE(two.find("fewer than three corners"), std::string::npos) << two;
  const std::string curve = obj_error("curve.obj", "v 0 0 0\ncurv 0 1 1\n");
  EXPECT_NE(curve.find("curve.obj:2: unsupported OBJ statement 'curv'"), std::string::npos) << curve;
  const std::string empty = obj_error("empty.obj", "# nothing\n");
  EXPECT_NE(empty.find("no faces"), std::string::npos) << empty;
  const std::string missing = test::load_error(test::data_path("bad/missing_mesh.dcg"));
  EXPECT_NE(missing.find("missing_mesh.dcg:3:"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no_such_mesh.obj: no such file"), std::string::npos) << missing;
}

}  // namespace
}  // namespace armfarm
