#pragma once
// Reading arm description files into a validated ArmModel. The format is chosen by the file
// extension: .urdf (urdfdom) or .dcg (the thesis's tag format, appendix B); trimesh bodies
// read Wavefront .obj meshes relative to the model file.
#include "engine/model/arm_model.hpp"
#include "engine/model/end_effector.hpp"

#include <stdexcept>
#include <string>

namespace armfarm {

/// A model file that cannot be read or is not a valid arm. what() is one line naming the
/// file and the place (line, element) and what is wrong.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The most links (URDF <link>s, DCG bodies B) and the most joints an arm model file may hold. A
/// file over it is refused before its tree is built ("FILE: 10001 links, over the cap of 1000"):
/// the arms armfarm studies have tens of links, and the physics of a job grows with their square.
inline constexpr int kMaxModelLinks = 1000;

/// Loads and validates an arm model and chooses its end effector (choose_end_effector:
/// `end_effector` when it names a link, else the file's, else the single leaf). Throws ModelError.
ArmModel load_arm_model(const std::string& path, const EndEffectorConfig& end_effector = {});

/// Loads and validates an arm model without requiring an end effector: end_effector.link is -1
/// when the file names none and has several leaves. For callers that need the file's structure
/// (its joints, the files it reads) before the choice is known. Throws ModelError.
ArmModel load_arm_model_file(const std::string& path);

/// --strict: throws ModelError with the first of `model.warnings`, if any.
void check_strict_model(const ArmModel& model);

}  // namespace armfarm
