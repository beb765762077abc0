// ArmModel::input_files: every file a loader read, the model first, then meshes once each in
// order of first use (the job key hashes them, runner/spec/input_files.hpp).
#include "engine/model/model_loading.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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
