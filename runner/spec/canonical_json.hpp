#pragma once
// Canonical JSON text and job keys (results/README.md, "Job keys"): sorted keys, no spaces,
// numbers written the same whatever their source form (1, 1.0 and 1e0 give "1"), so that a
// job's key depends only on its values.
#include <nlohmann/json.hpp>

#include <string>

namespace armfarm {

/// The canonical text of `value`.
std::string calc_canonical_json(const nlohmann::json& value);

/// XXH3-128 of `text` as 32 lowercase hex digits (high 64 bits first).
std::string calc_text_hash(const std::string& text);

/// The key of a job: calc_text_hash(calc_canonical_json(config)), where a configuration that
/// records input files (runner/spec/input_files.hpp) has its input paths replaced by their
/// content hashes first.
std::string calc_job_key(const nlohmann::json& config);

}  // namespace armfarm
