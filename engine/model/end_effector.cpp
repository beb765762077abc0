#include "engine/model/end_effector.hpp"

#include "engine/io/message_text.hpp"
#include "engine/model/model_loading.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>
#include <stdexcept>

namespace armfarm {
namespace {

// "'a', 'b', 'c'"; past kListedItems names, "… and N more" (a message stays one short line).
std::string quoted_names(const ArmModel& model, const std::vector<int>& links) {
  std::vector<std::string> names;
  for (const int link : links) names.push_back("'" + model.links[link].name + "'");
  return join_shortened(names);
}

}  // namespace

const std::vector<ConfigKey<EndEffectorConfig>>& end_effector_config_keys() {
  using C = EndEffectorConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"link", "", {}, ListSize::any,
       "the model link that tracks task-space targets; \"\" = the file's choice, else its single leaf link",
       [](C& c) { return make_field(c.link); }},
      {"offset", "m", {}, ListSize::any, "the end-effector point in that link's frame; needs end_effector.link",
       [](C& c) { return make_field(c.offset); }},
  };
  return keys;
}

std::string check_end_effector_config(const EndEffectorConfig& choice) {
  if (!choice.offset.allFinite()) return "the offset must be finite";
  if (choice.link.empty() && !choice.offset.isZero(0.0)) return "an offset needs end_effector.link (the link it is measured in)";
  return "";
}

EndEffectorConfig parse_end_effector_text(const std::string& text) {
  EndEffectorConfig choice;
  const std::size_t colon = text.find(':');
  choice.link = text.substr(0, colon);
  const auto bad = [&](const std::string& why) {
    throw std::invalid_argument("--ee '" + text + "': " + why + " (expected LINK or LINK:x,y,z, offset in metres)");
  };
  if (choice.link.empty()) bad("no link name");
  if (colon == std::string::npos) return choice;
  std::vector<double> values;
  std::string rest = text.substr(colon + 1);
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = rest.find(',', start);
    const std::string token = rest.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(token.c_str(), &end);
    if (token.empty() || end != token.c_str() + token.size() || errno == ERANGE || !std::isfinite(value)) {
      bad("'" + token + "' is not a finite number");
    }
    values.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (values.size() != 3) bad("the offset needs three numbers");
  choice.offset = Eigen::Vector3d(values[0], values[1], values[2]);
  return choice;
}

std::vector<int> find_leaf_links(const ArmModel& model) {
  std::set<int> parents;
  for (const Joint& joint : model.joints) parents.insert(joint.parent_link);
  // Whether some joint moves the link: a movable joint on its path from the root (joints are in
  // tree order, so a parent's answer is known before its children's).
  std::vector<bool> moved(model.links.size(), false);
  for (const Joint& joint : model.joints) {
    moved[joint.child_link] = moved[joint.parent_link] || joint.type != JointType::fixed;
  }
  std::vector<int> leaves;
  for (int l = 0; l < static_cast<int>(model.links.size()); ++l) {
    if (l != model.root_link && !model.links[l].fixed_to_world && moved[l] && parents.count(l) == 0) leaves.push_back(l);
  }
  return leaves;
}

void choose_end_effector(ArmModel& model, const EndEffectorConfig& choice) {
  const std::string problem = check_end_effector_config(choice);
  if (!problem.empty()) throw ModelError(model.source_file + ": end effector: " + problem);
  if (!choice.link.empty()) {
    const int link = model.find_link(choice.link);
    if (link < 0) {
      throw ModelError(model.source_file + ": end_effector.link: no link '" + choice.link + "' (leaf links: " +
                       quoted_names(model, find_leaf_links(model)) + ")");
    }
    model.end_effector = {link, choice.offset};
    return;
  }
  if (model.end_effector.link >= 0) return;  // the file's own choice
  const std::vector<int> leaves = find_leaf_links(model);
  if (leaves.size() == 1) {
    model.end_effector = {leaves[0], Eigen::Vector3d::Zero()};
    return;
  }
  if (leaves.empty()) throw ModelError(model.source_file + ": no leaf link to serve as the end effector (nothing moves)");
  throw ModelError(model.source_file + ": " + std::to_string(leaves.size()) + " leaf links (" + quoted_names(model, leaves) +
                   "): set end_effector.link to the one that tracks the targets (in a spec's base or as a grid axis; "
                   "--ee LINK[:x,y,z] on armfarm job and the model commands)");
}

}  // namespace armfarm
