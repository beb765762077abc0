// Bounded and linear model loading (issue 30, case 7 and "Bounded and linear"): URDF and DCG
// files over kMaxModelLinks are refused with one line naming the file and the count; a
// 999-link chain loads correctly (its tree order and reach checked against the closed form;
// timings are in bench_model_loading, not here); a 1000-leaf file's message stays one short line;
// urdfdom's console messages never reach the terminal and its reason is in the one line; a DCG
// mesh that is a symbolic link out of the model's folder is refused before it is opened.
#include "engine/model/arm_reach.hpp"
#include "engine/model/model_loading.hpp"

#include <gtest/gtest.h>

#include "support/big_models.hpp"
#include "support/scratch_file.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

// The ModelError of loading `text` written to a scratch file named `name`, or "(loaded)".
std::string load_problem(const std::string& name, const std::string& text, ArmModel* loaded = nullptr) {
  const std::string path = test_support::scratch_file(name);
  std::ofstream(path, std::ios::binary) << text;
  std::string problem = "(loaded)";
  try {
    ArmModel model = load_arm_model(path);
    if (loaded != nullptr) *loaded = std::move(model);
  } catch (const ModelError& error) {
    problem = error.what();
  }
  std::remove(path.c_str());
  return problem;
}

TEST(ModelSize, TenThousandLinkUrdfIsRefusedInOneLineNamingFileAndCount) {
  const std::string problem = load_problem("big.urdf", test_support::make_big_urdf(10000, false));
  EXPECT_EQ(problem, test_support::scratch_file("big.urdf") + ": 10001 links, over the cap of 1000 per arm model");
  // Just over the cap: 1000 links plus the base.
  EXPECT_NE(load_problem("big.urdf", test_support::make_big_urdf(1000, false)).find(": 1001 links, over the cap"),
            std::string::npos);
}

TEST(ModelSize, TenThousandBodyDcgIsRefusedInOneLine) {
  EXPECT_EQ(load_problem("big.dcg", test_support::make_big_dcg(10000)),
            test_support::scratch_file("big.dcg") + ": 10000 bodies, over the cap of 1000 per arm model");
}

TEST(ModelSize, NineHundredNinetyNineLinkChainLoadsInTreeOrder) {
  ArmModel model;
  ASSERT_EQ(load_problem("chain.urdf", test_support::make_big_urdf(999, false), &model), "(loaded)");
  ASSERT_EQ(model.links.size(), 1000u);  // at the cap
  ASSERT_EQ(model.joints.size(), 999u);
  for (int j = 0; j < 999; ++j) {  // a chain: joint j moves link j + 1 (l_j) and hangs from the previous one
    EXPECT_EQ(model.links[model.joints[j].child_link].name, "l" + std::to_string(j));
    if (j > 0) {
      EXPECT_EQ(model.joints[j].parent_link, model.joints[j - 1].child_link);
    }
  }
  EXPECT_EQ(model.links[model.end_effector.link].name, "l998");  // the one leaf
  // Closed form: 999 joint origins 0.01 m apart on z, the end effector at the last one's frame.
  EXPECT_NEAR(calc_reach(model), 998 * 0.01, 1e-9);

  ArmModel dcg;
  ASSERT_EQ(load_problem("chain.dcg", test_support::make_big_dcg(1000), &dcg), "(loaded)");
  EXPECT_EQ(dcg.links.size(), 1001u);  // the synthetic world and 1000 bodies
  EXPECT_EQ(dcg.movable_joints().size(), 999u);
}

TEST(ModelSize, AThousandLeavesGiveOneShortLine) {
  const std::string problem = load_problem("star.urdf", test_support::make_big_urdf(999, true));
  EXPECT_EQ(problem.find('\n'), std::string::npos);
  EXPECT_LT(problem.size(), 400u) << problem.size();
  EXPECT_NE(problem.find("999 leaf links ('l0', 'l1', "), std::string::npos) << problem;
  EXPECT_NE(problem.find("'l9' … and 989 more)"), std::string::npos) << problem;
}

TEST(ModelSize, UrdfdomPrintsNothingAndItsReasonIsInTheOneLine) {
  // urdfdom rejects a joint type the tinyxml2 pass does not check; it used to print 2 "Error:"
  // lines of its own (each with "at line N in ./urdf_parser/src/joint.cpp") on stderr.
  std::string urdf = test_support::make_big_urdf(2, false);
  urdf.replace(urdf.find("type=\"revolute\""), 15, "type=\"bogus\"");
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const std::string problem = load_problem("bogus.urdf", urdf);
  const std::string printed = testing::internal::GetCapturedStderr() + testing::internal::GetCapturedStdout();
  EXPECT_EQ(printed, "");
  EXPECT_EQ(problem.find('\n'), std::string::npos);
  EXPECT_NE(problem.find("bogus.urdf: not a valid URDF: urdfdom rejected it: Joint [j0] has no known type [bogus]"),
            std::string::npos)
      << problem;
}

TEST(ModelSize, MeshSymlinkOutOfTheModelFolderIsNotOpened) {
  const fs::path folder = test_support::make_scratch_folder("mesh_link");
  const fs::path outside = test_support::make_scratch_folder("mesh_outside");
  std::ofstream(outside / "secret.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  fs::create_directories(folder / "obj");
  fs::create_symlink(outside / "secret.obj", folder / "obj" / "tip.obj");
  const std::string dcg = "<DCGraph>\nB base <t(0 0 0)> o(1) s(0.1 0.1 0.1) fix;\nB tip <> o(3) f[obj/tip.obj] m(1000);\n"
                          "J base-tip <t(0 0 0.1)>;\n</DCGraph>\n";
  std::ofstream(folder / "arm.dcg") << dcg;
  std::string problem = "(loaded)";
  try {
    load_arm_model((folder / "arm.dcg").string());
  } catch (const ModelError& error) {
    problem = error.what();
  }
  EXPECT_EQ(problem, (folder / "arm.dcg").string() +
                         ":3: body 'tip': f[...]: 'obj/tip.obj' is a symbolic link (or passes through one) to a file "
                         "outside the model file's folder; files a model names must lie inside it");
  // The same link pointing inside the folder is followed.
  fs::copy_file(outside / "secret.obj", folder / "inside.obj");
  fs::remove(folder / "obj" / "tip.obj");
  fs::create_symlink(folder / "inside.obj", folder / "obj" / "tip.obj");
  EXPECT_NO_THROW(load_arm_model((folder / "arm.dcg").string()));
  fs::remove_all(folder);
  fs::remove_all(outside);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from engine/model/model_input_files_test.cpp:
// ArmModel::input_files: every file a loader read, the model first, then meshes once each in
// order of first use (the job key hashes them, runner/spec/input_files.hpp).

namespace armfarm {
namespace {

const std::string kModels = std::string(ARMFARM_TEST_DATA_DIR) + "/models/";

TEST(ModelInputFiles, UrdfReadsOnlyItself) {
  const std::string path = std::string(ARMFARM_SOURCE_DIR) + "/models/planar2.urdf";
  EXPECT_EQ(load_arm_model(path).input_files, std::vector<std::string>{path});
}

TEST(ModelInputFiles, DcgListsItsMeshesAfterItself) {
  const ArmModel model = load_arm_model(kModels + "small.dcg");
  const std::vector<std::string> expected = {kModels + "small.dcg", kModels + "obj/thesis_unit_box.obj",
                                             kModels + "obj/unit_cube_mixed.obj"};
  EXPECT_EQ(model.input_files, expected);
}

}  // namespace
}  // namespace armfarm
