#include "engine/experiment/job_model.hpp"

#include "engine/experiment/job_config_validation.hpp"

#include "engine/model/end_effector.hpp"
#include "engine/model/model_loading.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {

ArmModel make_job_model(const ArmModel& file_model, const JobConfig& config) {
  ArmModel model = file_model;
  choose_end_effector(model, config.end_effector);
  if (config.start_posture.size() == 0) return model;
  const std::vector<int> movable = model.movable_joints();
  if (config.start_posture.size() != static_cast<Eigen::Index>(movable.size())) {
    throw ConfigProblemError({"start_posture", "has " + std::to_string(config.start_posture.size()) + " values; " +
                                                   model.source_file + " has " + std::to_string(movable.size()) + " joints", "", std::nullopt});
  }
  for (std::size_t i = 0; i < movable.size(); ++i) {
    model.joints[movable[i]].start_position = config.start_posture[static_cast<Eigen::Index>(i)];
  }
  return model;
}

std::string check_job_model(const ArmModel& model, const JobConfig& config) {
  if (model.end_effector.link < 0) return "no end effector chosen (make the job's model with make_job_model)";
  if (config.start_posture.size() == 0) return "";
  const std::vector<int> movable = model.movable_joints();
  if (config.start_posture.size() != static_cast<Eigen::Index>(movable.size())) return "start_posture does not fit the model";
  for (std::size_t i = 0; i < movable.size(); ++i) {
    if (model.joints[movable[i]].start_position != config.start_posture[static_cast<Eigen::Index>(i)]) {
      return "the model's start posture is not start_posture (make the job's model with make_job_model)";
    }
  }
  return "";
}

}  // namespace armfarm
