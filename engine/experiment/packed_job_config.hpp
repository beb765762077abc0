#pragma once
// A ValidJobConfig kept small while its job waits to run. A sweep holds one checked configuration
// per job from its expansion to its execution (runner/execution/checked_experiment_job.hpp), and
// a JobConfig is 1.4 KB of structs and heap (sizeof 1360 bytes with g++ 12) of which a sweep's
// jobs mostly differ in two or three numbers. The packed form holds the keys whose values differ
// from a default JobConfig's, as bytes, and shares the file contents the runner read (recorded
// samples, an initial model) with the jobs that read the same file; unpack() gives back the same
// configuration, every key and file content bit for bit, without validating it again: only a
// ValidJobConfig can be packed, so a packed one is valid by construction.
//
// A JobConfig is its keys (job_config_keys()) and the file contents the runner reads for it
// (trajectory.recorded.samples and sample_lines, learning.initial_model_bytes): those are what
// the runner's reader sets (runner/config/job_config_json.cpp), and what is packed.
#include "engine/experiment/job_config_validation.hpp"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace armfarm {

/// The keys of `config` whose values differ from a default JobConfig's, each as its index in
/// job_config_keys(), its length and its value's bytes (numbers as their object representation,
/// lists and texts after their sizes); "" for a default configuration.
std::string pack_job_config_keys(const JobConfig& config);

/// A default JobConfig with the keys `packed` holds set, bit for bit as they were packed. Throws
/// std::logic_error on bytes pack_job_config_keys did not write.
JobConfig unpack_job_config_keys(const std::string& packed);

/// The file contents a configuration carries, shared between packed configurations.
struct JobFileData {
  Eigen::MatrixXd recorded_samples;
  std::vector<int> recorded_lines;
  std::string initial_model_bytes;
};

class PackedValidJobConfig {
 public:
  /// `valid` packed; `shared_files`: the file contents of the previously packed configuration
  /// (null: none), reused when `valid`'s are equal, so that a sweep's jobs hold one copy.
  explicit PackedValidJobConfig(const ValidJobConfig& valid, const std::shared_ptr<const JobFileData>& shared_files = nullptr);

  /// The configuration that was packed.
  ValidJobConfig unpack() const;
  /// The file contents it shares (null when it reads none).
  const std::shared_ptr<const JobFileData>& files() const { return files_; }
  /// Bytes held for it alone (the packed keys and the object), not those of the shared files.
  std::size_t calc_own_bytes() const;

 private:
  std::string values_;                       // per packed key: its index (4 bytes), length (4), bytes
  std::shared_ptr<const JobFileData> files_;
};

}  // namespace armfarm
