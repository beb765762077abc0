// Strict OBJ reading (issue 16): texture and normal indices, vt/vn/vp numbers and control
// characters are checked like the solid's own vertices and faces, with file and line.
#include "engine/model/model_loading.hpp"
#include "engine/model/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <cstdio>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

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

TEST(StrictObj, GoodCornersWithTextureAndNormalIndicesRead) {
  EXPECT_EQ(obj_problem(kTriangle + "vt 0 0\nvt 1 0\nvn 0 0 1\nf 1/1/1 2/2/1 3/-1/-1\n"), "(read)");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 0 1\nf 1//1 2//1 3//1\n"), "(read)");
  EXPECT_EQ(obj_problem(kTriangle + "f 1 2 3\r\n"), "(read)");  // CRLF line ends
}

TEST(StrictObj, GarbageOrNanInTextureOrNormalIndicesIsRefused) {
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

TEST(StrictObj, NonFiniteOrGarbageVtVnVpValuesAreRefused) {
  EXPECT_EQ(obj_problem(kTriangle + "vn -inf 0 1\nf 1 2 3\n"), ":4: vn value is not a finite number: '-inf'");
  EXPECT_EQ(obj_problem(kTriangle + "vt 0 nan\nf 1 2 3\n"), ":4: vt value is not a finite number: 'nan'");
  EXPECT_EQ(obj_problem(kTriangle + "vn 0 1\nf 1 2 3\n"), ":4: vn needs three numbers, got 2");
  EXPECT_EQ(obj_problem(kTriangle + "vp 1e999\nf 1 2 3\n"), ":4: vp value: '1e999' overflows a double (above 1.8e308 in magnitude)");
  EXPECT_EQ(obj_problem("v 0 1e-400 0\n"),
            ":1: vertex coordinate: '1e-400' underflows to zero (below 4.9e-324, the smallest double, in magnitude)");
  EXPECT_EQ(obj_problem("v 0 0 0 0x10\n"), ":1: vertex coordinate is not a finite number (a 4-byte token, not shown)");
}

TEST(StrictObj, ControlCharactersAndUnknownWordsAreRefusedWithoutQuotingThem) {
  EXPECT_EQ(obj_problem(std::string("v 0 0.5\0" "1 0\n", 12)), ":1: NUL at column 8");
  EXPECT_EQ(obj_problem("v 0 0.5\r1 0\n"), ":1: CR at column 8");
  EXPECT_EQ(obj_problem("root:x:0:0:root:/root:/bin/bash\n"),
            ":1: not an OBJ statement (only v and f define the solid; vt vn vp g o s usemtl mtllib are skipped)");
  EXPECT_EQ(obj_problem(kTriangle + "curv 0 1 1\n"), ":4: unsupported OBJ statement 'curv' (only v and f define the solid)");
}

}  // namespace
}  // namespace armfarm
