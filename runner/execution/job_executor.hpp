#pragma once
// The seam between the runner and the experiment job. The runner (expansion, scheduling,
// storage) only sees job configurations as JSON, what the schema's check made of them (opaque:
// CheckedConfig) and JobOutcome values; the experiment side provides the schema of a
// configuration and the function that runs one.
#include "engine/experiment/job_outcome.hpp"
#include "runner/spec/config_error.hpp"   // ConfigError, which an executor may throw
#include "runner/spec/config_schema.hpp"  // JobConfigSchema

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>

namespace armfarm {

/// Polled by a running job (about once per control tick, and before every update and scoring
/// prediction of batch training); when it returns true the job stops and returns with status
/// `timeout` (or is discarded by the runner on Ctrl-C).
struct JobControl {
  std::function<bool()> should_stop = [] { return false; };
};

/// Runs one fully resolved configuration. `checked`: what the schema's check made of `config`
/// when the job came through one (an expanded job: ExpandedJob::checked), which the executor
/// then neither parses nor validates again; null: the executor checks `config` itself, once (a
/// configuration read from a file or a database). Must not throw for failures of the job itself
/// (those become JobOutcome::status failed/diverged with a message); may throw ConfigError
/// for an invalid configuration.
using JobExecutor =
    std::function<JobOutcome(const nlohmann::json& config, const CheckedConfig* checked, const JobControl& control)>;

class StoredModels;

/// The experiment job's schema and executor (runner/execution/experiment_executor.cpp).
/// `stored`: the results database's learned models that jobs may start from (learning.initial_model
/// references resolve against it when a sweep expands); null: none.
JobConfigSchema make_experiment_config_schema(std::shared_ptr<StoredModels> stored = nullptr);
JobExecutor make_experiment_executor(std::shared_ptr<StoredModels> stored = nullptr);

}  // namespace armfarm
