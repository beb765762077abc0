#pragma once
// Job keys of the configurations of one sweep, without re-serializing each: they differ from a
// common configuration only at the elements the sweep's axes set. The canonical text of that
// configuration's key document (canonical_json.hpp) is cut once at those elements; a job's key
// hashes the pieces with the canonical text of its own values in between, which are the same
// bytes calc_job_key(config) hashes, so the same key.
#include "runner/spec/config_path.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace armfarm {

class JobKeyTemplate {
 public:
  /// `config`: one job configuration, its "inputs" recorded; `holes`: the paths of the elements
  /// that vary between the jobs this template serves. The template is unusable (usable() false)
  /// when a hole names an input file field or lies inside "inputs", when two holes overlap, or when
  /// the configuration cannot be cut cleanly at them.
  JobKeyTemplate(const nlohmann::json& config, const std::vector<ConfigPath>& holes);

  bool usable() const { return usable_; }

  /// The key of the configuration whose hole i holds the value with canonical text
  /// `values[i]` (calc_canonical_json). `scratch` is reused between calls.
  std::string calc_key(const std::vector<const std::string*>& values, std::string& scratch) const;

  /// Bytes held (the pieces of the canonical text).
  std::size_t calc_size() const;

 private:
  bool usable_ = false;
  std::vector<std::string> pieces_;  ///< pieces_.size() == holes + 1
  std::vector<std::size_t> order_;   ///< pieces_[k] is followed by the value of hole order_[k]
};

}  // namespace armfarm
