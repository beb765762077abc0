#include "engine/model/model_loading.hpp"

#include "engine/model/model_loaders.hpp"

#include <algorithm>
#include <cctype>

namespace armfarm {

ArmModel load_arm_model_file(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == "urdf") return load_urdf_model(path);
  if (extension == "dcg") return load_dcg_model(path);
  throw ModelError(path + ": unknown model format '." + extension + "' (expected .urdf or .dcg)");
}

ArmModel load_arm_model(const std::string& path, const EndEffectorConfig& end_effector) {
  ArmModel model = load_arm_model_file(path);
  choose_end_effector(model, end_effector);
  return model;
}

void check_strict_model(const ArmModel& model) {
  if (model.warnings.empty()) return;
  const std::size_t more = model.warnings.size() - 1;
  throw ModelError(model.warnings.front() + " (refused under --strict" +
                   (more > 0 ? "; " + std::to_string(more) + " more such element" + (more > 1 ? "s" : "") : "") + ")");
}

}  // namespace armfarm
