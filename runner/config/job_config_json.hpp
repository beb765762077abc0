#pragma once
// The experiment job's configuration as JSON, driven by the engine's key table
// (engine/experiment/job_config.hpp): the defaults tree is written from a default-constructed
// JobConfig (so every default has one home, its component's struct), and the parser reads every
// key through the same table, then runs the engine's validate() (job_config_validation.hpp).
// sweeps/README.md documents every key; a test keeps the two in step.
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/job_config_validation.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace armfarm {

/// The keys the runner adds to the engine's (the model file, which the engine receives loaded).
struct RunnerConfigKey {
  const char* path;
  const char* default_value;
  const char* doc;
};
const std::vector<RunnerConfigKey>& runner_config_keys();

/// Every key of a job configuration with its default (the JSON types are the expected types;
/// an empty array is a list of numbers).
nlohmann::json make_job_config_defaults();

/// make_job_config_defaults() with null at the keys whose value may be a number, a list or a
/// matrix (ValueKind real_or_list, real_matrix): the spec layer's type reference
/// (JobConfigSchema::types).
nlohmann::json make_job_config_types();

/// Parses a resolved configuration (defaults merged) for an arm with `movable_joints` movable
/// joints and validates it: the one validation at the edge, whose proof (ValidJobConfig,
/// job_config_validation.hpp) the engine's run_experiment takes without validating again. Throws ConfigError (runner/spec/config_error.hpp) naming the
/// JSON path of the first problem; its message lists every problem ("path: what; path: what").
/// `null` at a key means its default (configurations stored before the defaults were written out).
///
/// learning.initial_model: a model file path is read here into initial_model_bytes; a resolved
/// stored model ("stored:<hash>", runner/execution/stored_models.hpp) is fetched with
/// `stored_model_bytes(hash)`, which throws std::exception when it cannot (unset: such a
/// configuration is refused).
ValidJobConfig parse_job_config(const nlohmann::json& config, int movable_joints,
                           const std::function<std::string(const std::string& hash)>& stored_model_bytes = {});

/// The same, checked against everything known of the model: a joint-space recorded trajectory
/// must also stay within the joints' position limits (the first line outside them is named).
ValidJobConfig parse_job_config(const nlohmann::json& config, const ModelFacts& facts,
                           const std::function<std::string(const std::string& hash)>& stored_model_bytes = {});

/// The same for a configuration with its inputs recorded (runner/spec/input_files.hpp): each
/// recorded input field is read from its resolved path, i.e. it parses
/// calc_config_with_resolved_inputs(recorded) without copying the tree (the sweep check runs it
/// for every job).
/// The files parse_recorded_job_config reads (a recorded trajectory, a learner model to start
/// from), the last one of each kind kept by the content hash its configuration records: the jobs
/// of a sweep mostly name the same files, which are then read and parsed once for the sweep's
/// check instead of once a job. Holds at most one file of each kind; not thread-safe.
///
/// The contents are lent, not copied: parse_recorded_job_config moves a kept file's contents
/// into the configuration it returns (a sweep's recorded samples were copied once a job), and
/// return_job_file_contents moves them back once the caller is done with that configuration.
/// While lent, nothing is kept: a check that throws, or a configuration never returned, leaves
/// the next job to read the file again.
struct JobFileContents {
  std::string recorded_hash;  ///< of the samples and lines held; "" = none held
  Eigen::MatrixXd recorded_samples;
  std::vector<int> recorded_lines;
  std::string model_hash;  ///< of the model bytes held; "" = none held
  std::string model_bytes;
  /// The file lent to the last configuration returned: its hash and where its storage is, so
  /// that only that configuration's contents are taken back.
  struct Lent {
    std::string hash;
    const void* storage = nullptr;
  };
  Lent lent_recorded;
  Lent lent_model;
};

ValidJobConfig parse_recorded_job_config(const nlohmann::json& recorded, const ModelFacts& facts,
                                    const std::function<std::string(const std::string& hash)>& stored_model_bytes = {},
                                    JobFileContents* contents = nullptr);

/// Takes back into `contents` the file contents that the last parse_recorded_job_config with
/// `contents` lent to `valid` (nothing when `valid` is another configuration). `valid` is given
/// up: its recorded samples, lines and initial model bytes are left empty.
void return_job_file_contents(ValidJobConfig&& valid, JobFileContents& contents);

}  // namespace armfarm
