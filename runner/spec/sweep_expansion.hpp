#pragma once
// Expansion of a sweep spec into independent jobs: the product of every grid axis, every zip
// group, the random samples and the repeat seeds (the first axis varies slowest). Each job is
// the base configuration with the axes' values set, checked by the schema, keyed by the hash of
// its canonical text.
#include "runner/spec/config_schema.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armfarm {

/// One job, kept compact: a sweep holds only its key, the values its axes set and pointers to
/// parts every job shares (about 0.5 KB per job, tests/bench/bench_expansion.cpp, and the
/// experiment job's packed checked configuration, about 0.3 KB more); the full configuration (a
/// ~15 KB JSON tree) is built when asked for.
struct ExpandedJob {
  std::string key;         ///< calc_job_key(config())
  nlohmann::json params;   ///< the values the axes set, {"dotted.path": value}
  std::int64_t seed = 0;   ///< config()["seed"], 0 when the configuration has none
  std::shared_ptr<const nlohmann::json> base;    ///< the sweep's base configuration (shared)
  std::shared_ptr<const nlohmann::json> inputs;  ///< its "inputs" object (shared by equal ones); null: none
  /// The whole configuration, kept only when base + params + inputs cannot rebuild it (a
  /// reference resolved at expansion, e.g. learning.initial_model → "stored:<hash>"); null otherwise.
  std::shared_ptr<const nlohmann::json> full;
  /// What the schema's check made of config() at the expansion (JobConfigSchema::validate; the
  /// experiment job: its ValidJobConfig), handed to the executor and the cost estimate so that
  /// they do not parse and validate the configuration again; null when the schema keeps nothing.
  std::shared_ptr<const CheckedConfig> checked;

  /// The full resolved configuration: `base` with every `params` value set and `inputs`.
  nlohmann::json config() const;
  /// A job whose configuration is `config` as it is (no axes, not checked): for callers that
  /// build one.
  static ExpandedJob from_config(const nlohmann::json& config);
};

/// How large a sweep may be; `armfarm run` and `expand` take `--max-jobs`. The default, 10^5
/// jobs, is far beyond what finishes on one machine (the quick start's jobs take about 7 core
/// seconds each: 10^5 of them are 8 core-days), so a larger count is almost surely a typo
/// (two 1000-value axes); expanding 10^5 jobs takes seconds and well under 1 GB. Raise it for
/// a sharded cluster run.
/// `max_jobs` above kMaxSweepJobs is accepted but does not raise the limit past it: ten million
/// jobs take some 10 GB to expand (about 1 KB each), so a larger sweep is refused with a message
/// naming --max-jobs rather than failing inside the allocator.
struct ExpansionLimits {
  std::uint64_t max_jobs = 100000;
};

/// The most jobs one sweep expands into whatever --max-jobs says (ExpansionLimits).
inline constexpr std::uint64_t kMaxSweepJobs = 10000000;

/// How many configurations `spec` expands into before duplicates merge: the product of the grid
/// axes' sizes, the zip groups' lengths, the random samples and the repeat seeds (1 with no
/// axes); saturates at UINT64_MAX instead of overflowing.
std::uint64_t calc_expansion_count(const SweepSpec& spec);

struct ExpandedSweep {
  SweepSpec spec;
  std::vector<ExpandedJob> jobs;  ///< in expansion order; duplicate configurations appear once
  std::string spec_hash;          ///< hash of the canonical list of job keys
};

/// How the expansion assembles each job's configuration tree and key. `fast` edits one tree in
/// place and sets it back after each job, and hashes a key from a text cut up once per distinct
/// "inputs" (JobKeyTemplate); `plain` copies the base for each job and hashes the whole tree.
/// Both give the same jobs, keys and spec hash (tests/runner/spec/sweep_expansion_test.cpp
/// compares them); `plain` is the reference, `fast` what armfarm runs.
enum class JobAssemblyMethod { fast, plain };

/// Expands and checks every job with schema.validate. Throws SpecError naming the spec location
/// of the value that failed (or the base configuration), and, before expanding anything, when
/// calc_expansion_count(spec) exceeds limits.max_jobs ("FILE: sweep: expands to N jobs, over
/// the limit of M; --max-jobs raises it").
ExpandedSweep expand_sweep(SweepSpec spec, const JobConfigSchema& schema, const ExpansionLimits& limits = {},
                           JobAssemblyMethod method = JobAssemblyMethod::fast);

}  // namespace armfarm
