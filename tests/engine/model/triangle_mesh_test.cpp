// OBJ reading: corner forms, relative indices, polygon fans, merged duplicates and errors, and
// the strict checks of texture and normal indices, vt/vn/vp numbers and control characters.
#include "engine/model/triangle_mesh.hpp"

#include "engine/model/model_loading.hpp"
#include "tests/engine/model/model_test_helpers.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>
#include <string>

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

// Strict reading (issue 16): texture and normal indices, vt/vn/vp numbers and control
// characters are checked like the solid's own vertices and faces, with file and line.

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

// The ModelError of reading `text` as an OBJ file, after the file name; "(read)" if it reads.
std::string obj_problem(const std::string& text) {
  const std::string path = test_support::scratch_file("strict.obj");
  std::ofstream(path, std::ios::binary) << text;
  std::string problem = "(read)";
  try {
    load_obj_mesh(path);
  } catch (const ModelError& error) {
    problem = std::string(error.what()).substr(path.size());
  }
  std::remove(path.c_str());
  return problem;
}

TEST(TriangleMesh, GoodCornersWithTextureAndNormalIndicesRead) {
  EXPECT_EQ(obj_problem(kTriangle + "vt 0 0\nvt 1 0\nvn 0 0 1\nf 1/1/1 2/2/1 3/-1/-1\n"), "(read)");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 0 1\nf 1//1 2//1 3//1\n"), "(read)");
  EXPECT_EQ(obj_problem(kTriangle + "f 1 2 3\r\n"), "(read)");  // CRLF line ends
}

TEST(TriangleMesh, GarbageOrNanInTextureOrNormalIndicesIsRefused) {
  EXPECT_EQ(obj_problem(kTriangle + "vt 0 0\nvn 0 0 1\nf 1/x/1 2/1/1 3/1/1\n"),
            ":6: face corner 1: texture coordinate index is not an integer (a 1-byte token, not shown)");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 0 1\nf 1//nan 2//1 3//1\n"),
            ":5: face corner 1: normal index is not an integer: 'nan'");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 0 1\nf 1//1 2//1 3//1.5\n"),
            ":5: face corner 3: normal index is not an integer: '1.5'");
  EXPECT_EQ(obj_problem(kTriangle + "f 1/1 2/1 3/1\n"),
            ":4: face corner 1 refers to texture coordinate 1 but only 0 texture coordinates precede it");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 0 1\nf 1//2 2//1 3//1\n"),
            ":5: face corner 1 refers to normal 2 but only 1 normals precede it");
  EXPECT_EQ(obj_problem(kTriangle + "f 1/1/1/1 2 3\n"), ":4: face corner 1 has more than v/vt/vn");
}

TEST(TriangleMesh, NonFiniteOrGarbageVtVnVpValuesAreRefused) {
  EXPECT_EQ(obj_problem(kTriangle + "vn -inf 0 1\nf 1 2 3\n"), ":4: vn value is not a finite number: '-inf'");
  EXPECT_EQ(obj_problem(kTriangle + "vt 0 nan\nf 1 2 3\n"), ":4: vt value is not a finite number: 'nan'");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 1\nf 1 2 3\n"), ":4: vn needs three numbers, got 2");
  EXPECT_EQ(obj_problem(kTriangle + "vp 1e999\nf 1 2 3\n"), ":4: vp value: '1e999' overflows a double (above 1.8e308 in magnitude)");
  EXPECT_EQ(obj_problem("v 0 1e-400 0\n"),
            ":1: vertex coordinate: '1e-400' underflows to zero (below 4.9e-324, the smallest double, in magnitude)");
  EXPECT_EQ(obj_problem("v 0 0 0 0x10\n"), ":1: vertex coordinate is not a finite number (a 4-byte token, not shown)");
}

TEST(TriangleMesh, ControlCharactersAndUnknownWordsAreRefusedWithoutQuotingThem) {
  EXPECT_EQ(obj_problem(std::string("v 0 0.5\0" "1 0\n", 12)), ":1: NUL at column 8");
  EXPECT_EQ(obj_problem("v 0 0.5\r1 0\n"), ":1: CR at column 8");
  EXPECT_EQ(obj_problem("root:x:0:0:root:/root:/bin/bash\n"),
            ":1: not an OBJ statement (only v and f define the solid; vt vn vp g o s usemtl mtllib are skipped)");
  EXPECT_EQ(obj_problem(kTriangle + "curv 0 1 1\n"), ":4: unsupported OBJ statement 'curv' (only v and f define the solid)");
}

}  // namespace
}  // namespace armfarm
