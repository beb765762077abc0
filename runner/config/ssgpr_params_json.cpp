// SSGPR params JSON → SsgprLearningConfig, through the learning.ssgpr key table.
#include "runner/config/ssgpr_params_json.hpp"

#include "base/number_format.hpp"
#include "runner/config/config_value_json.hpp"
#include "runner/spec/json_document.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace armfarm {
namespace {

}  // namespace

SsgprLearningConfig parse_ssgpr_params(const nlohmann::json& json, const std::string& source) {
  const auto fail = [&source](const std::string& key, const std::string& what) {
    throw std::runtime_error(source + ": " + key + ": " + what);
  };
  if (!json.is_object()) throw std::runtime_error(source + ": expected a JSON object of SSGPR parameters");
  const auto& keys = ssgpr_learning_config_keys();
  SsgprLearningConfig config;
  for (const auto& [key, v] : json.items()) {
    const auto found = std::find_if(keys.begin(), keys.end(), [&key = key](const auto& k) { return key == k.name; });
    if (found == keys.end()) {
      std::string known;
      for (const auto& k : keys) known += (known.empty() ? "" : ", ") + std::string(k.name);
      fail(key, "unknown parameter (known: " + known + ")");
    }
    std::string suffix;
    const FieldRef field = found->field(config);
    const std::string problem = read_field_json(v, field, suffix, {});
    if (!problem.empty()) fail(key + suffix, problem);
    const auto check = [&](double value, const std::string& where) {
      if (!found->range.contains(value)) fail(where, format_number(value) + " is outside the allowed range " + found->range.describe());
    };
    switch (field.kind) {
      case ValueKind::integer: check(static_cast<double>(field.get_integer(field.field)), key); break;
      case ValueKind::real: check(field.real(), key); break;
      case ValueKind::real_or_list:
      case ValueKind::real_list:
        for (Eigen::Index i = 0; i < field.vector().size(); ++i) check(field.vector()(i), key + "[" + std::to_string(i) + "]");
        break;
      default: break;
    }
  }
  if (config.fit_samples == 1) fail("fit_samples", "is 1; give 0 (no fit) or at least 2 samples");
  return config;
}

SsgprLearningConfig load_ssgpr_params(const std::string& path) {
  return parse_ssgpr_params(read_json_file(path), path);
}

}  // namespace armfarm
