#pragma once
// Choosing the end effector of an arm: the point that tracks task-space targets, a link and an
// offset in that link's frame. The choice comes from the job configuration (`end_effector.link`,
// `end_effector.offset`) or the command line (`--ee LINK[:x,y,z]`), else from the file
// (URDF <armfarm:end_effector>, DCG ee(...)), else it is the arm's single leaf link. A file with
// several leaves and no choice is an error that lists the leaves and says how to choose.
#include "engine/config/config_key.hpp"
#include "engine/model/arm_model.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace armfarm {

/// The user's end-effector choice. Empty `link`: the file's choice or its single leaf (then
/// `offset` must be zero). `offset` in metres, in the named link's frame.
struct EndEffectorConfig {
  std::string link;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};
const std::vector<ConfigKey<EndEffectorConfig>>& end_effector_config_keys();

/// "" when `choice` is consistent on its own, else the problem (an offset without a link).
std::string check_end_effector_config(const EndEffectorConfig& choice);

/// Reads `LINK` or `LINK:x,y,z` (offset in metres). Throws std::invalid_argument naming the
/// text when it is malformed.
EndEffectorConfig parse_end_effector_text(const std::string& text);

/// Indices of the links no joint hangs from, other than the root, links fixed to the world and
/// frames welded to the base (no movable joint between them and the root: a vendor's 'base'
/// frame never moves): the tips of the tree, in link order.
std::vector<int> find_leaf_links(const ArmModel& model);

/// Sets `model.end_effector`: `choice.link` when given (any link of the model), else the file's
/// choice (model.end_effector.link >= 0), else the single leaf with offset zero. Throws
/// ModelError naming model.source_file when the link is unknown or when there are several
/// leaves and nothing chooses (the message lists the leaves and the ways to choose).
void choose_end_effector(ArmModel& model, const EndEffectorConfig& choice);

}  // namespace armfarm
