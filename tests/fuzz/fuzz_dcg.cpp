// Fuzz target: DCG arm models (engine/model/dcg_loading, through load_arm_model). The scratch
// folder holds obj/ with the test meshes (tests/data/models/obj), so the seed corpus's
// f[obj/...] trimesh bodies load. A well-formed rejection is a ModelError.
#include "engine/model/model_loading.hpp"
#include "tests/fuzz/fuzz_input.hpp"

#include <filesystem>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool meshes_copied = [] {
    namespace fs = std::filesystem;
    fs::create_directories(armfarm::fuzz::scratch_folder() / "obj");
    for (const auto& entry : fs::directory_iterator(ARMFARM_FUZZ_MESH_FOLDER)) {
      if (entry.path().extension() == ".obj") {
        fs::copy_file(entry.path(), armfarm::fuzz::scratch_folder() / "obj" / entry.path().filename(),
                      fs::copy_options::overwrite_existing);
      }
    }
    return true;
  }();
  (void)meshes_copied;
  const std::string path = armfarm::fuzz::write_scratch(data, size, ".dcg");
  try {
    armfarm::load_arm_model(path);
  } catch (const armfarm::ModelError&) {
  }
  return 0;
}
