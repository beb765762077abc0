// The experiment job as the runner sees it: JSON configuration → engine JobConfig → one
// run_experiment() call. Arm models are loaded once per file and shared (read-only) by the
// jobs of a sweep. The files a job reads (model and meshes, recorded trajectory) are its input
// fields: the spec layer resolves and hashes them, and the job loads them from the resolved
// paths recorded under "inputs".
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/input_files.hpp"

#include <cstdlib>

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace armfarm {
namespace {

/// Arm models by file path, loaded on first use. Thread-safe; models are immutable once loaded.
class ModelCache {
 public:
  std::shared_ptr<const ArmModel> get(const std::string& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = models_.find(path);
    if (found != models_.end()) return found->second;
    std::shared_ptr<const ArmModel> model;
    try {
      model = std::make_shared<const ArmModel>(load_arm_model(path));
    } catch (const std::exception& error) {
      throw ConfigError("model", error.what());
    }
    models_.emplace(path, model);
    return model;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const ArmModel>> models_;
};

// Where the default model (and any other default path) resolves: $ARMFARM_DATA_DIR, else the
// source tree armfarm was built from.
std::string find_data_folder() {
  const char* folder = std::getenv("ARMFARM_DATA_DIR");
  if (folder != nullptr && *folder != '\0') return folder;
  return ARMFARM_DEFAULT_DATA_DIR;
}

}  // namespace

JobConfigSchema make_experiment_config_schema() {
  auto models = std::make_shared<ModelCache>();
  JobConfigSchema schema;
  schema.defaults = make_job_config_defaults();
  schema.types = make_job_config_types();
  schema.validate = [models](const nlohmann::json& recorded) {
    const nlohmann::json config = calc_config_with_resolved_inputs(recorded);
    const auto model = models->get(config.at("model").get<std::string>());
    parse_job_config(config, make_model_facts(*model));
  };
  InputFileField model_field;
  model_field.path = "model";
  model_field.list_files = [models](const std::string& resolved) {
    try {
      return models->get(resolved)->input_files;
    } catch (const ConfigError& error) {
      const std::string message = error.what();  // "model: FILE: problem"
      throw std::runtime_error(message.substr(error.json_path().empty() ? 0 : error.json_path().size() + 2));
    }
  };
  InputFileField recorded_field;
  recorded_field.path = "trajectory.recorded.file";
  recorded_field.is_read = [](const nlohmann::json& config) {
    return config.at("trajectory").at("kind") == "recorded";
  };
  schema.input_files = {model_field, recorded_field};
  schema.default_folder = find_data_folder();
  return schema;
}

JobExecutor make_experiment_executor() {
  auto models = std::make_shared<ModelCache>();
  return [models](const nlohmann::json& recorded, const JobControl& control) -> JobOutcome {
    const nlohmann::json config = calc_config_with_resolved_inputs(recorded);
    const auto model = models->get(config.at("model").get<std::string>());
    const JobConfig job = parse_job_config(config, make_model_facts(*model));
    JobOutcome outcome;
    try {
      outcome = run_experiment(*model, job, control.should_stop);
    } catch (const std::invalid_argument& error) {
      throw ConfigError("", error.what());
    } catch (const std::exception& error) {
      outcome.status = JobStatus::failed;
      outcome.message = error.what();
    }
    return outcome;
  };
}

}  // namespace armfarm
