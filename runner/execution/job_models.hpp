#pragma once
// The arm models of a sweep's jobs, loaded once per file and made once per distinct choice of
// end effector and start posture (engine/experiment/job_model.hpp: make_job_model, the one
// place a configuration is applied to a model). Thread-safe; models are immutable once made.
// The expansion check and the executor (experiment_executor.cpp) and the job-cost estimate
// (job_cost.cpp) each hold one.
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/model/arm_model.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace armfarm {

class JobModels {
 public:
  /// The file's arm before a job's choices are applied (its joints, its input files).
  /// ConfigError at "model" when the file is bad.
  std::shared_ptr<const ArmModel> get_file(const std::string& path);

  /// The arm a job with `config` runs on: make_job_model(file, config). ConfigError at
  /// "model" when the file is bad, at "end_effector.link" when the end effector cannot be chosen
  /// (the message names the file, lists its leaf links and the key to set).
  std::shared_ptr<const ArmModel> get(const std::string& path, const JobConfig& config);

  /// What validate() checks a job of this file against (make_model_facts), made once per file:
  /// it builds a Simbody system. ConfigError at "model" when the file is bad.
  std::shared_ptr<const ModelFacts> get_facts(const std::string& path);

 private:
  std::shared_ptr<const ArmModel> get_file_locked(const std::string& path);

  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const ArmModel>> files_;
  std::map<std::string, std::shared_ptr<const ArmModel>> made_;  // path, end effector, start posture
  std::map<std::string, std::shared_ptr<const ModelFacts>> facts_;
};

}  // namespace armfarm
