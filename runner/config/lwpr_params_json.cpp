// LWPR params JSON → LwprParams, through LWPR's key table (engine/learning/learning_config.hpp).
#include "runner/config/lwpr_params_json.hpp"

#include "base/did_you_mean.hpp"
#include "engine/learning/learning_config.hpp"
#include "runner/config/config_value_json.hpp"
#include "runner/spec/json_document.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace armfarm {

lwpr::LwprParams parse_lwpr_params(const nlohmann::json& json, const std::string& source, int n_in,
                                   const LwprDataScales& scales) {
  const auto fail = [&source](const std::string& key, const std::string& what) {
    throw std::runtime_error(source + ": " + key + ": " + what);
  };
  if (!json.is_object()) throw std::runtime_error(source + ": expected a JSON object of LWPR parameters");
  const auto& keys = lwpr_params_keys();
  FieldReadOptions options;
  options.flags_as_numbers = true;        // the library's files write flags as 0/1
  options.case_insensitive_names = true;  // and "Gaussian", "BiSquare"
  lwpr::LwprParams p;
  for (const auto& [key, v] : json.items()) {
    const auto found = std::find_if(keys.begin(), keys.end(), [&key = key](const auto& k) { return key == k.name; });
    if (found == keys.end()) {
      std::vector<std::string> names;
      for (const auto& k : keys) names.push_back(k.name);
      fail(key, "unknown parameter" + make_did_you_mean(key, names, NameMatch{3, true}));
    }
    if ((key == "norm_in" || key == "norm_out") && v.is_string()) {
      const bool in = key == "norm_in";
      if (v.get<std::string>() != "std") fail(key, "expected a number, a list or \"std\", got " + v.dump());
      Eigen::VectorXd scale = in ? scales.input_std : scales.output_std;
      if (scale.size() == 0) fail(key, "\"std\" needs training data");
      for (Eigen::Index i = 0; i < scale.size(); ++i) {
        if (!(scale(i) > 0.0)) fail(key, "\"std\": dimension " + std::to_string(i) + " is constant in the training data");
      }
      (in ? p.norm_in : p.norm_out) = scale;
      continue;
    }
    std::string suffix;
    const FieldRef field = found->field(p);
    const std::string problem = read_field_json(v, field, suffix, options);
    if (!problem.empty()) fail(key + suffix, problem);
    // Counts are checked here; real-valued ranges of raw-data fits are left to
    // lwpr::validate_lwpr_params (the job's tighter ranges assume normalised inputs).
    if (field.kind == ValueKind::integer && !found->range.contains(static_cast<double>(field.get_integer(field.field)))) {
      fail(key, "expected an integer in " + found->range.describe() + ", got " + v.dump());
    }
  }
  (void)n_in;
  return p;
}

lwpr::LwprParams load_lwpr_params(const std::string& path, int n_in, const LwprDataScales& scales) {
  return parse_lwpr_params(read_json_file(path), path, n_in, scales);
}

}  // namespace armfarm
