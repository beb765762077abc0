#pragma once
// The shape of a job configuration as the runner's spec layer sees it: defaults (and so types),
// the check of a resolved configuration, and which values name files the job reads.
#include "engine/config/config_key.hpp"
#include "runner/spec/config_error.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// A configuration value that names a file the job reads (the arm model, a recorded
/// trajectory, later a learned model to start from). Relative paths resolve against the folder
/// of the file that wrote the value; the job key hashes the files' bytes instead of the path.
struct InputFileField {
  std::string path;  ///< dotted path of the string element, e.g. "trajectory.recorded.file"
  /// Whether the job reads the file under `config`; unset: whenever the value is non-empty.
  std::function<bool(const nlohmann::json& config)> is_read;
  /// Every file that reading it opens, given its resolved path: the file itself first, then the
  /// files it references (a model's meshes). Unset: just the file. Throws std::exception with a
  /// one-line message when the input cannot be read.
  std::function<std::vector<std::string>(const std::string& resolved_path)> list_files;
};

/// What a schema's check made of one configuration (the experiment job: its ValidJobConfig,
/// runner/execution/experiment_executor.cpp). The runner never looks inside: it carries it with
/// the job from the expansion to the kind's executor and cost estimate, so that a configuration
/// is parsed and validated once, where its JSON enters.
class CheckedConfig {
 public:
  virtual ~CheckedConfig() = default;
};

/// A schema's check of one resolved configuration: what it made of it (null: a kind that keeps
/// nothing), or ConfigError with the path of the first problem.
using ConfigCheck = std::function<std::shared_ptr<const CheckedConfig>(const nlohmann::json& config)>;

/// `defaults` holds every key with its default value (the JSON types are the expected types;
/// an empty array means "array of numbers"); `validate` checks ranges and cross-field rules of
/// a fully resolved configuration (its input paths resolved, see runner/spec/input_files.hpp),
/// throwing ConfigError with the path, and returns what it made of it (ConfigCheck).
struct JobConfigSchema {
  nlohmann::json defaults;
  /// The tree the structural check of specs compares values with: `defaults`, except that keys
  /// taking several shapes (a number, a list or a matrix, e.g. learning.lwpr.init_D) are null,
  /// i.e. free-form there and checked by `validate`. Null: use `defaults`.
  nlohmann::json types;
  const nlohmann::json& type_reference() const { return types.is_null() ? defaults : types; }
  ConfigCheck validate;
  /// A `validate` for many configurations in a row (one sweep's expansion), made once for it and
  /// dropped after: it may keep what the configurations share (files they read) between calls.
  /// Unset: `validate`.
  std::function<ConfigCheck()> make_sweep_validate;
  std::vector<InputFileField> input_files;
  /// Resolves values that name stored results (learning.initial_model's stored-model references,
  /// runner/execution/stored_models.hpp) in a job's configuration when the sweep expands, before
  /// its input files are recorded; returns whether it changed `config`. Throws
  /// std::runtime_error "dotted.path: problem". Unset: none.
  std::function<bool(nlohmann::json& config)> resolve_references;
  /// The allowed range of the number at a dotted path, from the key table (a search axis's
  /// bounds must lie inside it). Unset, or empty for a path: no range is known.
  std::function<std::optional<Range>(const std::string& path)> find_key_range;
  /// Where input paths that no file wrote (the defaults) resolve: the armfarm data directory.
  std::string default_folder = ".";
};

}  // namespace armfarm
