#pragma once
// What the experiment job's schema check (runner/execution/experiment_executor.cpp) makes of a
// configuration: the engine's ValidJobConfig, the proof of the one validation, packed
// (engine/experiment/packed_job_config.hpp: the keys that differ from the defaults, the file
// contents shared between the jobs that read the same files), and the model file it was validated
// against, shared too. An expanded job carries it (ExpandedJob::checked) to the executor, which
// runs it without parsing or validating the JSON again, and to the cost estimate.
#include "engine/experiment/packed_job_config.hpp"
#include "runner/spec/config_schema.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm {

struct CheckedExperimentJob final : CheckedConfig {
  CheckedExperimentJob(PackedValidJobConfig valid, std::shared_ptr<const std::string> model)
      : job(std::move(valid)), model(std::move(model)) {}

  const std::string& model_path() const { return *model; }

  PackedValidJobConfig job;  ///< parsed and validated against the model's facts, its files' contents read; unpack() runs it
  std::shared_ptr<const std::string> model;  ///< the model file the job loads (the resolved path its inputs record)
};

/// `checked` as the experiment job's; null when it is null. Throws std::logic_error when another
/// job kind's check made it (a programming error: a job is checked by its own kind's schema).
inline const CheckedExperimentJob* find_checked_experiment_job(const CheckedConfig* checked) {
  if (checked == nullptr) return nullptr;
  const auto* experiment = dynamic_cast<const CheckedExperimentJob*>(checked);
  if (experiment == nullptr) throw std::logic_error("a job checked by another job kind's schema reached the experiment job");
  return experiment;
}

}  // namespace armfarm
