#pragma once
// The per-format loaders behind load_arm_model (model_loading.hpp). Each reads its file with
// read_model_file (model_file.hpp), builds an ArmModel in tree order (calc_tree_order) and
// validates it; each throws ModelError. The end effector is the file's own choice, or -1 when
// the file names none (choose_end_effector, end_effector.hpp, picks the single leaf or asks).
#include "engine/model/arm_model.hpp"

#include <string>

namespace armfarm {

/// URDF via urdfdom, plus what urdfdom skips, read with tinyxml2: <transmission> blocks
/// (armature = rotorInertia · mechanicalReduction²) and the armfarm extension elements
/// <armfarm:end_effector link=".." offset="x y z"/> and
/// <armfarm:start_position joint=".." value=".."/> (models/README.md).
ArmModel load_urdf_model(const std::string& path);

/// The thesis's DCG tag format (appendix B/C) with armfarm's documented extensions.
ArmModel load_dcg_model(const std::string& path);

}  // namespace armfarm
