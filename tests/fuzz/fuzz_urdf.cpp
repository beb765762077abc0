// Fuzz target: URDF arm models (engine/model/urdf_loading, through load_arm_model: parsing and
// validation). A well-formed rejection is a ModelError.
#include "engine/model/model_loading.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = armfarm::fuzz::write_scratch(data, size, ".urdf");
  try {
    armfarm::load_arm_model(path);
  } catch (const armfarm::ModelError&) {
  }
  return 0;
}
