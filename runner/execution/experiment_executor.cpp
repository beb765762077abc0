// The experiment job as the runner sees it: JSON configuration → engine JobConfig, validated
// once where the JSON enters (the schema's check at the expansion, whose CheckedExperimentJob the
// job carries to the executor; or the executor itself for a configuration that comes without
// one) → one run_experiment() call. Arm models are loaded once per file and shared (read-only) by the
// jobs of a sweep. The files a job reads (model and meshes, recorded trajectory) are its input
// fields: the spec layer resolves and hashes them, and the job loads them from the resolved
// paths recorded under "inputs". The arm a job runs on is make_job_model's (job_models.hpp). Trajectories are built once per distinct trajectory key and
// shared read-only by the jobs that use it (trajectory_cache.hpp).
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/io/input_file.hpp"
#include "engine/model/model_loading.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/checked_experiment_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/execution/job_models.hpp"
#include "runner/execution/stored_models.hpp"
#include "runner/execution/trajectory_cache.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/input_files.hpp"

#include <cstdlib>
#include <exception>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace armfarm {
namespace {

// True when `error` was thrown for a ModelError (JobModels nests the cause in its ConfigError).
bool is_caused_by_model_error(const ConfigError& error) {
  try {
    std::rethrow_if_nested(error);
  } catch (const ModelError&) {
    return true;
  } catch (...) {
    return false;
  }
  return false;
}

// The "model" input: the model file and every file it reads (meshes), as `models` loads them.
InputFileField make_model_field(const std::shared_ptr<JobModels>& models) {
  InputFileField field;
  field.path = "model";
  field.list_files = [models](const std::string& resolved) {
    try {
      return models->get_file(resolved)->input_files;
    } catch (const ConfigError& error) {
      // Without the "model" path. A ModelError from loading `resolved` names it first ("FILE: problem",
      // model_loading.hpp), which list_files says by throwing InputFileError (runner/spec/input_files.cpp);
      // other causes do not.
      if (is_caused_by_model_error(error)) throw InputFileError(error.message());
      throw std::runtime_error(error.message());
    }
  };
  return field;
}

/// The content hash of each model file as the executor loaded it, computed once per file right
/// after its first load, so that a job never runs on a model whose bytes differ from those its
/// key names. Thread-safe.
class ModelHashCheck {
 public:
  explicit ModelHashCheck(const std::shared_ptr<JobModels>& models) : field_(make_model_field(models)) {}

  /// Throws ConfigError at "model" when `recorded` names a model hash that the loaded file's is not.
  void check(const nlohmann::json& recorded, const std::string& resolved_path) {
    const std::string recorded_hash = find_recorded_input_hash(recorded, "model");
    if (recorded_hash.empty()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    std::string now;
    try {
      now = reader_.read(field_, resolved_path).hash;
    } catch (const std::exception& error) {
      throw ConfigError("model", error.what());
    }
    if (now != recorded_hash) throw ConfigError("model", make_input_changed_text(resolved_path, recorded_hash, now));
  }

 private:
  std::mutex mutex_;
  InputFileField field_;
  InputFileReader reader_;  // caches each file's hash: the model is loaded once per run too
};

// Where the default model (and any other default path) resolves: $ARMFARM_DATA_DIR, else the
// source tree armfarm was built from.
std::string find_data_folder() {
  const char* folder = std::getenv("ARMFARM_DATA_DIR");
  if (folder != nullptr && *folder != '\0') return folder;
  return ARMFARM_DEFAULT_DATA_DIR;
}

// The bytes of resolved stored models, by hash; unset without a database.
std::function<std::string(const std::string&)> make_stored_model_reader(const std::shared_ptr<StoredModels>& stored) {
  if (!stored) return {};
  return [stored](const std::string& hash) { return stored->find_bytes(hash); };
}

// The model file a recorded configuration's job loads: the resolved path its inputs record, else
// the value as written.
std::string find_model_path(const nlohmann::json& recorded) {
  const nlohmann::json* resolved = find_resolved_input(recorded, "model");
  return (resolved != nullptr ? *resolved : recorded.at("model")).get<std::string>();
}

// What one sweep's checks share: the files they read (read once), and the model path and file
// contents of the last job checked, which the next job's packed configuration reuses when equal.
struct SweepCheckShare {
  JobFileContents contents;
  std::shared_ptr<const std::string> model_path;
  std::shared_ptr<const JobFileData> files;
};

// The check of a configuration with its inputs recorded: parsed and validated against its model,
// the job's model made (end effector, start posture), packed. ConfigError naming the path of the
// first problem. `share`: the sweep's (null: a configuration checked alone).
std::shared_ptr<const CheckedExperimentJob> check_config(const nlohmann::json& recorded, JobModels& models,
                                                         const std::shared_ptr<StoredModels>& stored, SweepCheckShare* share) {
  const std::string path = find_model_path(recorded);
  ValidJobConfig job =
      parse_recorded_job_config(recorded, *models.get_facts(path), make_stored_model_reader(stored), share ? &share->contents : nullptr);
  models.get(path, job);
  std::shared_ptr<const std::string> model_path = share && share->model_path && *share->model_path == path
                                                      ? share->model_path
                                                      : std::make_shared<const std::string>(path);
  PackedValidJobConfig packed(job, share ? share->files : nullptr);
  if (share) {
    share->model_path = model_path;
    share->files = packed.files();
    return_job_file_contents(std::move(job), share->contents);  // packed: the next job borrows them
  }
  return std::make_shared<const CheckedExperimentJob>(std::move(packed), std::move(model_path));
}

}  // namespace

JobConfigSchema make_experiment_config_schema(std::shared_ptr<StoredModels> stored) {
  auto models = std::make_shared<JobModels>();
  JobConfigSchema schema;
  schema.defaults = make_job_config_defaults();
  schema.types = make_job_config_types();
  schema.validate = [models, stored](const nlohmann::json& recorded) -> std::shared_ptr<const CheckedConfig> {
    return check_config(recorded, *models, stored, nullptr);
  };
  schema.make_sweep_validate = [models, stored] {
    auto share = std::make_shared<SweepCheckShare>();  // the sweep's recorded trajectory and initial model, read once
    return ConfigCheck([models, stored, share](const nlohmann::json& recorded) -> std::shared_ptr<const CheckedConfig> {
      return check_config(recorded, *models, stored, share.get());
    });
  };
  schema.find_key_range = [](const std::string& path) -> std::optional<Range> {
    for (const JobConfigKey& key : job_config_keys()) {
      if (key.path == path) return key.range;
    }
    return std::nullopt;
  };
  schema.resolve_references = [stored](nlohmann::json& config) {
    // Only a reference object (or null, which means none and is removed) is rewritten.
    const auto learning = config.find("learning");
    if (learning == config.end() || !learning->is_object()) return false;
    const auto initial = learning->find("initial_model");
    if (initial == learning->end() || !(initial->is_object() || initial->is_null())) return false;
    resolve_stored_model_reference(config, stored.get());
    return true;
  };
  const InputFileField model_field = make_model_field(models);
  InputFileField recorded_field;
  recorded_field.path = "trajectory.recorded.file";
  recorded_field.is_read = [](const nlohmann::json& config) {
    return config.at("trajectory").at("kind") == "recorded";
  };
  // A model file to start from (a resolved stored model is named by its hash, not a file).
  InputFileField initial_model_field;
  initial_model_field.path = "learning.initial_model";
  initial_model_field.is_read = [](const nlohmann::json& config) {
    const auto learning = config.find("learning");
    if (learning == config.end() || !learning->is_object()) return false;
    const nlohmann::json value = learning->value("initial_model", nlohmann::json());
    return value.is_string() && value.get<std::string>().rfind(kStoredModelPrefix, 0) != 0;
  };
  schema.input_files = {model_field, recorded_field, initial_model_field};
  schema.default_folder = find_data_folder();
  return schema;
}

JobExecutor make_experiment_executor(std::shared_ptr<StoredModels> stored) {
  auto models = std::make_shared<JobModels>();
  auto trajectories = std::make_shared<TrajectoryCache>();
  auto model_hashes = std::make_shared<ModelHashCheck>(models);
  return [models, trajectories, stored, model_hashes](const nlohmann::json& recorded, const CheckedConfig* checked,
                                                      const JobControl& control) -> JobOutcome {
    // Every file the job reads is the one its key names: the model is loaded now and checked
    // against the hash its key recorded; the recorded trajectory and the initial model are the
    // bytes the check read and compared with those hashes (at the expansion when the job comes
    // checked, else now, by parse_recorded_job_config).
    const CheckedExperimentJob* carried = find_checked_experiment_job(checked);
    const std::string path = carried != nullptr ? carried->model_path() : find_model_path(recorded);
    std::optional<ValidJobConfig> valid;
    if (carried == nullptr) {
      const std::shared_ptr<const ModelFacts> facts = models->get_facts(path);
      model_hashes->check(recorded, path);
      valid.emplace(parse_recorded_job_config(recorded, *facts, make_stored_model_reader(stored)));
    } else {
      model_hashes->check(recorded, path);
      valid.emplace(carried->job.unpack());
    }
    const ValidJobConfig& job = *valid;
    const auto model = models->get(path, job);
    JobOutcome outcome;
    try {
      const std::shared_ptr<const JobTrajectories> shared =
          trajectories->get(make_trajectory_key(recorded), [&] { return build_job_trajectories(*model, job); });
      outcome = run_experiment(*model, job, *shared, control.should_stop);
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
