#pragma once
// The seam between the runner and the experiment job. The runner (expansion, scheduling,
// storage) only sees job configurations as JSON and JobOutcome values; the experiment side
// provides the schema of a configuration and the function that runs one.
#include "engine/experiment/job_outcome.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <stdexcept>
#include <string>

namespace armfarm {

/// A job configuration that is not valid. `json_path` is a JSON pointer-like dotted path
/// ("control.kp[2]", "trajectory.kind"); callers prefix the file name.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string json_path, const std::string& message)
      : std::runtime_error(json_path.empty() ? message : json_path + ": " + message),
        json_path_(std::move(json_path)) {}
  const std::string& json_path() const { return json_path_; }

 private:
  std::string json_path_;
};

/// Polled by a running job (about once per control tick); when it returns true the job stops
/// and returns with status `timeout` (or is discarded by the runner on Ctrl-C).
struct JobControl {
  std::function<bool()> should_stop = [] { return false; };
};

/// Runs one fully resolved configuration. Must not throw for failures of the job itself
/// (those become JobOutcome::status failed/diverged with a message); may throw ConfigError
/// for an invalid configuration.
using JobExecutor = std::function<JobOutcome(const nlohmann::json& config, const JobControl& control)>;

/// The shape of a job configuration: `defaults` holds every key with its default value (the
/// JSON types are the expected types; an empty array means "array of numbers"), and
/// `validate` checks ranges and cross-field rules of a fully resolved configuration,
/// throwing ConfigError with the path.
struct JobConfigSchema {
  nlohmann::json defaults;
  std::function<void(const nlohmann::json& config)> validate;
};

/// The experiment job's schema and executor (runner/execution/experiment_executor.cpp).
JobConfigSchema make_experiment_config_schema();
JobExecutor make_experiment_executor();

}  // namespace armfarm
