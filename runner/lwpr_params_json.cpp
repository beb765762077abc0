// LWPR params JSON → LwprParams, through LWPR's key table (engine/learning/learning_config.hpp).
#include "runner/lwpr_params_json.hpp"

#include "engine/io/input_file.hpp"
#include "engine/learning/learning_config.hpp"
#include "runner/config/config_value_json.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace armfarm {
namespace {

std::size_t calc_edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

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
      std::string best;
      std::size_t best_distance = 4;
      for (const auto& k : keys) {
        const std::size_t d = calc_edit_distance(key, k.name);
        if (d < best_distance) {
          best_distance = d;
          best = k.name;
        }
      }
      fail(key, "unknown parameter" + (best.empty() ? std::string() : " (did you mean '" + best + "'?)"));
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
  const std::string text = read_input_file(path, InputFileKind::json);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(path + ": invalid JSON at byte " + std::to_string(e.byte));
  }
  return parse_lwpr_params(json, path, n_in, scales);
}

}  // namespace armfarm
