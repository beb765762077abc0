#pragma once
// Expansion of a sweep spec into independent jobs: the product of every grid axis, every zip
// group, the random samples and the repeat seeds (the first axis varies slowest). Each job is
// the base configuration with the axes' values set, checked by the schema, keyed by the hash of
// its canonical text.
#include "runner/config/config_schema.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace armfarm {

struct ExpandedJob {
  std::string key;         ///< calc_job_key(config)
  nlohmann::json params;   ///< the values the axes set, {"dotted.path": value}
  nlohmann::json config;   ///< the full resolved configuration
  std::int64_t seed = 0;   ///< config["seed"], 0 when the configuration has none
};

struct ExpandedSweep {
  SweepSpec spec;
  std::vector<ExpandedJob> jobs;  ///< in expansion order; duplicate configurations appear once
  std::string spec_hash;          ///< hash of the canonical list of job keys
};

/// Expands and checks every job with schema.validate. Throws SpecError naming the spec location
/// of the value that failed (or the base configuration).
ExpandedSweep expand_sweep(SweepSpec spec, const JobConfigSchema& schema);

}  // namespace armfarm
