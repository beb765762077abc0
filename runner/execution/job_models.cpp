#include "runner/execution/job_models.hpp"

#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/job_model.hpp"
#include "engine/model/model_loading.hpp"
#include "runner/spec/config_error.hpp"
#include "runner/spec/canonical_json.hpp"

#include <nlohmann/json.hpp>

#include <exception>

namespace armfarm {
namespace {

// The choices make_job_model reads, as one text.
std::string make_choice_key(const std::string& path, const JobConfig& config) {
  const Eigen::Vector3d& offset = config.end_effector.offset;
  nlohmann::json posture = nlohmann::json::array();
  for (Eigen::Index i = 0; i < config.start_posture.size(); ++i) posture.push_back(config.start_posture[i]);
  return path + "\n" + config.end_effector.link + "\n" +
         calc_canonical_json(nlohmann::json::array({offset.x(), offset.y(), offset.z()})) + "\n" + calc_canonical_json(posture);
}

}  // namespace

std::shared_ptr<const ArmModel> JobModels::get_file(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  return get_file_locked(path);
}

std::shared_ptr<const ArmModel> JobModels::get(const std::string& path, const JobConfig& config) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string key = make_choice_key(path, config);
  auto found = made_.find(key);
  if (found != made_.end()) return found->second;
  const std::shared_ptr<const ArmModel> file = get_file_locked(path);
  std::shared_ptr<const ArmModel> made;
  try {
    made = std::make_shared<const ArmModel>(make_job_model(*file, config));
  } catch (const ModelError& error) {
    throw ConfigError("end_effector.link", error.what());
  } catch (const ConfigProblemError& error) {
    throw ConfigError(error.problem().path, error.problem().message);
  }
  made_.emplace(key, made);
  return made;
}

std::shared_ptr<const ModelFacts> JobModels::get_facts(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto found = facts_.find(path);
  if (found != facts_.end()) return found->second;
  auto facts = std::make_shared<const ModelFacts>(make_model_facts(*get_file_locked(path)));
  facts_.emplace(path, facts);
  return facts;
}

std::shared_ptr<const ArmModel> JobModels::get_file_locked(const std::string& path) {
  auto found = files_.find(path);
  if (found != files_.end()) return found->second;
  std::shared_ptr<const ArmModel> model;
  try {
    model = std::make_shared<const ArmModel>(load_arm_model_file(path));
  } catch (const std::exception& error) {
    std::throw_with_nested(ConfigError("model", error.what()));  // the cause stays readable by its type
  }
  files_.emplace(path, model);
  return model;
}

}  // namespace armfarm
