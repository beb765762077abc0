// LWPR params JSON → LwprParams.
#include "runner/lwpr_params_json.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace armfarm {
namespace {

const std::vector<std::string>& known_keys() {
  static const std::vector<std::string> keys = {
      "init_D",      "init_alpha",   "penalty",       "diag_only", "update_D", "meta",     "meta_rate",
      "w_gen",       "w_prune",      "init_lambda",   "final_lambda", "tau_lambda", "init_S2", "add_threshold",
      "kernel",      "norm_in",      "norm_out",      "blend",     "add_proj", "init_n_reg", "max_fields",
      "cutoff",      "trust_n_data"};
  return keys;
}

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

struct Context {
  const std::string& source;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::runtime_error(source + ": " + key + ": " + what);
  }
  double number(const nlohmann::json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, got " + v.dump());
    return v.get<double>();
  }
  bool flag(const nlohmann::json& v, const std::string& key) const {
    if (v.is_boolean()) return v.get<bool>();
    if (v.is_number_integer() && (v.get<int>() == 0 || v.get<int>() == 1)) return v.get<int>() == 1;
    fail(key, "expected true/false (or 0/1), got " + v.dump());
  }
  Eigen::VectorXd vector(const nlohmann::json& v, const std::string& key) const {
    if (v.is_number()) return Eigen::VectorXd::Constant(1, v.get<double>());
    if (!v.is_array() || v.empty()) fail(key, "expected a number or a list of numbers");
    Eigen::VectorXd out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out(i) = number(v[i], key + "[" + std::to_string(i) + "]");
    return out;
  }
};

}  // namespace

lwpr::LwprParams parse_lwpr_params(const nlohmann::json& json, const std::string& source, int n_in,
                                   const LwprDataScales& scales) {
  const Context ctx{source};
  if (!json.is_object()) throw std::runtime_error(source + ": expected a JSON object of LWPR parameters");
  lwpr::LwprParams p;
  for (const auto& [key, v] : json.items()) {
    if (key == "init_D") {
      if (v.is_array() && !v.empty() && v[0].is_array()) {
        p.init_D.resize(v.size(), v[0].size());
        for (std::size_t i = 0; i < v.size(); ++i) {
          if (!v[i].is_array() || v[i].size() != v[0].size()) ctx.fail(key, "rows of different lengths");
          for (std::size_t j = 0; j < v[i].size(); ++j) {
            p.init_D(i, j) = ctx.number(v[i][j], key + "[" + std::to_string(i) + "][" + std::to_string(j) + "]");
          }
        }
      } else {
        p.init_D = ctx.vector(v, key);
      }
    } else if (key == "init_alpha") {
      p.init_alpha = ctx.number(v, key);
    } else if (key == "penalty") {
      p.penalty = ctx.number(v, key);
    } else if (key == "diag_only") {
      p.diag_only = ctx.flag(v, key);
    } else if (key == "update_D") {
      p.update_D = ctx.flag(v, key);
    } else if (key == "meta") {
      p.meta = ctx.flag(v, key);
    } else if (key == "meta_rate") {
      p.meta_rate = ctx.number(v, key);
    } else if (key == "w_gen") {
      p.w_gen = ctx.number(v, key);
    } else if (key == "w_prune") {
      p.w_prune = ctx.number(v, key);
    } else if (key == "init_lambda") {
      p.init_lambda = ctx.number(v, key);
    } else if (key == "final_lambda") {
      p.final_lambda = ctx.number(v, key);
    } else if (key == "tau_lambda") {
      p.tau_lambda = ctx.number(v, key);
    } else if (key == "init_S2") {
      p.init_S2 = ctx.number(v, key);
    } else if (key == "add_threshold") {
      p.add_threshold = ctx.number(v, key);
    } else if (key == "kernel") {
      const std::string k = v.is_string() ? v.get<std::string>() : "";
      if (k == "gaussian" || k == "Gaussian") {
        p.kernel = lwpr::Kernel::kGaussian;
      } else if (k == "bisquare" || k == "BiSquare") {
        p.kernel = lwpr::Kernel::kBisquare;
      } else {
        ctx.fail(key, "expected \"gaussian\" or \"bisquare\", got " + v.dump());
      }
    } else if (key == "norm_in" || key == "norm_out") {
      const bool in = key == "norm_in";
      if (v.is_string()) {
        if (v.get<std::string>() != "std") ctx.fail(key, "expected a number, a list or \"std\", got " + v.dump());
        Eigen::VectorXd scale = in ? scales.input_std : scales.output_std;
        if (scale.size() == 0) ctx.fail(key, "\"std\" needs training data");
        for (Eigen::Index i = 0; i < scale.size(); ++i) {
          if (!(scale(i) > 0.0)) ctx.fail(key, "\"std\": dimension " + std::to_string(i) + " is constant in the training data");
        }
        (in ? p.norm_in : p.norm_out) = scale;
      } else {
        (in ? p.norm_in : p.norm_out) = ctx.vector(v, key);
      }
    } else if (key == "blend") {
      p.blend = ctx.flag(v, key);
    } else if (key == "add_proj") {
      p.add_proj = ctx.flag(v, key);
    } else if (key == "init_n_reg") {
      if (!v.is_number_integer()) ctx.fail(key, "expected an integer");
      p.init_n_reg = v.get<int>();
    } else if (key == "max_fields") {
      if (!v.is_number_integer() || v.get<long long>() < 0) ctx.fail(key, "expected an integer >= 0");
      p.max_fields = v.get<std::size_t>();
    } else if (key == "cutoff") {
      p.cutoff = ctx.number(v, key);
    } else if (key == "trust_n_data") {
      p.trust_n_data = ctx.number(v, key);
    } else {
      std::string best;
      std::size_t best_distance = 4;
      for (const auto& k : known_keys()) {
        const std::size_t d = calc_edit_distance(key, k);
        if (d < best_distance) {
          best_distance = d;
          best = k;
        }
      }
      ctx.fail(key, "unknown parameter" + (best.empty() ? std::string() : " (did you mean '" + best + "'?)"));
    }
  }
  (void)n_in;
  return p;
}

lwpr::LwprParams load_lwpr_params(const std::string& path, int n_in, const LwprDataScales& scales) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::runtime_error(path + ": invalid JSON at byte " + std::to_string(e.byte));
  }
  return parse_lwpr_params(json, path, n_in, scales);
}

}  // namespace armfarm
