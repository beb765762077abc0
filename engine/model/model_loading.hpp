#pragma once
// Reading arm description files into a validated ArmModel. The format is chosen by the file
// extension: .urdf (urdfdom) or .dcg (the thesis's tag format, appendix B); trimesh bodies
// read Wavefront .obj meshes relative to the model file.
#include "engine/model/arm_model.hpp"

#include <stdexcept>
#include <string>

namespace armfarm {

/// A model file that cannot be read or is not a valid arm. what() is one line naming the
/// file and the place (line, element) and what is wrong.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Loads and validates an arm model. Throws ModelError.
ArmModel load_arm_model(const std::string& path);

}  // namespace armfarm
