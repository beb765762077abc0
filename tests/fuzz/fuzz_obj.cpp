// Fuzz target: Wavefront OBJ meshes (engine/model/triangle_mesh) and their mass properties.
// A well-formed rejection is a ModelError; anything else (a crash, a sanitizer report, another
// exception) is a finding.
#include "engine/model/mass_properties.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/model/triangle_mesh.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = armfarm::fuzz::write_scratch(data, size, ".obj");
  try {
    const armfarm::TriangleMesh mesh = armfarm::load_obj_mesh(path);
    armfarm::calc_mesh_mass_properties(mesh);
  } catch (const armfarm::ModelError&) {
  }
  return 0;
}
