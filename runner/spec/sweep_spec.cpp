#include "runner/spec/sweep_spec.hpp"

#include "base/did_you_mean.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/experiment/metric_catalog.hpp"
#include "engine/io/input_file.hpp"

#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_check.hpp"
#include "runner/spec/input_files.hpp"
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_spec_positions.hpp"
#include "runner/search/search_sequence.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace armfarm {
namespace {

std::string read_text_file(const std::string& path, const std::string& referenced_from) {
  try {
    return read_input_file(path, InputFileKind::json);
  } catch (const InputFileError& error) {
    throw SpecError({(referenced_from.empty() ? "" : referenced_from + ": ") + error.what()});
  }
}

// `["key"]` → `.key` where the key needs no quotes, so that spec locations and document paths compare.
std::string normalize_location(const std::string& location) {
  std::string out;
  for (std::size_t i = 0; i < location.size();) {
    if (location.compare(i, 2, "[\"") == 0) {
      const std::size_t close = location.find("\"]", i + 2);
      if (close != std::string::npos) {
        const std::string key = location.substr(i + 2, close - i - 2);
        if (!key.empty() && key.find_first_of(".[]\" \\") == std::string::npos) {
          out += "." + key;
          i = close + 2;
          continue;
        }
      }
    }
    out += location[i++];
  }
  return out;
}

// "FILE: path: problem (line L, column C)" for a problem of calc_checked_value, located by its
// path; "FILE: path: problem" under SpecPositions::omitted.
std::string locate_line(const std::string& file, const JsonDocument& document, const CheckedValueProblem& problem,
                        SpecPositions positions) {
  if (positions == SpecPositions::omitted) return file + ": " + problem.line();
  const std::string where = document.describe_position(normalize_location(problem.path));
  return file + ": " + problem.line() + (where.empty() ? "" : " (" + where + ")");
}

std::string quoted(const std::string& parent, const std::string& key) { return parent + "[\"" + key + "\"]"; }

class SpecParser {
 public:
  SpecParser(const std::string& file, const std::string& folder, const JobConfigSchema& schema, SpecPositions positions)
      : file_(file), folder_(folder), schema_(schema), positions_(positions) {}

  SweepSpec parse(const std::string& text) {
    SweepSpec spec;
    spec.file = file_;
    spec.folder = folder_;
    spec.text = text;
    document_ = parse_json_document(text, file_);
    const nlohmann::json& root = document_.value;
    if (!root.is_object()) throw SpecError({file_ + ": (top level): a sweep spec is a JSON object"});
    check_keys(root, "", {"name", "description", "base", "include", "sweep", "comment"});

    if (!root.contains("name")) {
      error("name", "missing; every sweep needs a name");
    } else if (!root["name"].is_string() || root["name"].get<std::string>().empty()) {
      error("name", "expected a non-empty string");
    } else {
      spec.name = root["name"].get<std::string>();
    }
    if (root.contains("description")) {
      if (root["description"].is_string()) {
        spec.description = root["description"].get<std::string>();
      } else {
        error("description", "expected a string");
      }
    }

    resolved_ = schema_.defaults;
    if (root.contains("include")) read_includes(root["include"]);
    if (root.contains("base")) {
      std::vector<CheckedValueProblem> lines;
      const nlohmann::json base = calc_checked_value(root["base"], schema_.type_reference(), "base", lines);
      for (const CheckedValueProblem& line : lines) errors_.push_back(locate_line(file_, document_, line, positions_));
      if (lines.empty()) merge_config_into(resolved_, base);
    }
    spec.base = resolved_;
    spec.includes = includes_;

    if (root.contains("sweep")) {
      const nlohmann::json& sweep = root["sweep"];
      if (!sweep.is_object()) {
        error("sweep", "expected an object with grid, zip, random and/or repeat");
      } else {
        check_keys(sweep, "sweep", {"grid", "zip", "random", "repeat", "search"});
        if (sweep.contains("grid")) read_grid(sweep["grid"], spec);
        if (sweep.contains("zip")) read_zip(sweep["zip"], spec);
        if (sweep.contains("random")) read_random(sweep["random"], spec);
        if (sweep.contains("repeat")) read_repeat(sweep["repeat"], spec);
        if (sweep.contains("search")) {
          for (const char* other : {"grid", "zip", "random", "repeat"}) {
            if (sweep.contains(other)) {
              error(std::string("sweep.") + other, "does not combine with sweep.search (a search decides its own jobs)");
            }
          }
          read_search(sweep["search"], spec);
        }
      }
    }
    if (!errors_.empty()) throw SpecError(errors_);
    spec.input_folders = calc_input_folders(root, spec);
    spec.input_writers = writers_;
    return spec;
  }

 private:
  // Who wrote each input field: this spec (base or an axis), else the last include, else nobody.
  std::map<std::string, std::string> calc_input_folders(const nlohmann::json& root, const SweepSpec& spec) {
    std::map<std::string, std::string> folders;
    std::vector<ConfigPath> axes;
    for (const SpecAxis& axis : spec.grid) axes.push_back(axis.segments);
    for (const SpecZipGroup& group : spec.zip) {
      for (const SpecAxis& axis : group.axes) axes.push_back(axis.segments);
    }
    if (spec.random) {
      for (const SpecRandomParam& param : spec.random->params) axes.push_back(param.segments);
    }
    if (spec.search) {
      for (const SpecSearchAxis& axis : spec.search->axes) axes.push_back(axis.segments);
    }
    for (const InputFileField& field : schema_.input_files) {
      const ConfigPath segments = parse_config_path(field.path);
      std::string problem;
      bool written_here = root.contains("base") && find_config_element(root["base"], segments, problem) != nullptr;
      for (const auto& axis : axes) written_here = written_here || axis.overlaps(segments);
      const auto from_include = input_folders_.find(field.path);
      folders[field.path] = written_here ? folder_ : from_include != input_folders_.end() ? from_include->second : schema_.default_folder;
      if (!written_here && from_include != input_folders_.end()) writers_[field.path] = input_writers_.at(field.path);
    }
    return folders;
  }

  void error(const std::string& path, const std::string& message) {
    errors_.push_back(file_ + ": " + (path.empty() ? "(top level)" : path) + ": " + message);
  }

  void check_keys(const nlohmann::json& object, const std::string& path, const std::vector<std::string>& allowed) {
    for (const auto& item : object.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
        error(path.empty() ? item.key() : path + "." + item.key(), "unknown key" + make_did_you_mean(item.key(), allowed));
      }
    }
  }

  void read_includes(const nlohmann::json& include) {
    std::vector<std::string> names;
    if (include.is_string()) {
      names.push_back(include.get<std::string>());
    } else if (include.is_array()) {
      for (std::size_t i = 0; i < include.size(); ++i) {
        if (include[i].is_string()) {
          names.push_back(include[i].get<std::string>());
        } else {
          error("include[" + std::to_string(i) + "]", "expected a file name");
        }
      }
    } else {
      error("include", "expected a file name or a list of file names");
      return;
    }
    for (const std::string& name : names) {
      const std::string path = (std::filesystem::path(folder_) / name).lexically_normal().string();
      JsonDocument document;
      std::string text;
      try {
        text = read_text_file(path, file_ + ": include");
        document = parse_json_document(text, path);
      } catch (const SpecError& e) {
        errors_.insert(errors_.end(), e.lines().begin(), e.lines().end());
        continue;
      }
      std::vector<CheckedValueProblem> lines;
      const nlohmann::json checked = calc_checked_value(document.value, schema_.type_reference(), "", lines);
      for (const CheckedValueProblem& line : lines) errors_.push_back(locate_line(path, document, line, positions_));
      if (!lines.empty()) continue;
      merge_config_into(resolved_, checked);
      const std::string include_folder = std::filesystem::path(path).parent_path().string();
      for (const InputFileField& field : schema_.input_files) {
        std::string problem;
        if (find_config_element(checked, parse_config_path(field.path), problem) != nullptr) {
          input_folders_[field.path] = include_folder.empty() ? "." : include_folder;
          input_writers_[field.path] = path;
        }
      }
      includes_.push_back({name, calc_resolved_path(path, "."), calc_text_hash(text)});
    }
  }

  // Resolves a dotted path of an axis; false (with an error) when it names nothing.
  bool resolve_path(const std::string& path, const std::string& location, ConfigPath& segments,
                    const nlohmann::json*& reference) {
    try {
      segments = parse_config_path(path);
    } catch (const std::invalid_argument& e) {
      error(location, "'" + path + "' is not a dotted path: " + e.what());
      return false;
    }
    std::string problem;
    if (find_config_element(resolved_, segments, problem) == nullptr) {
      error(location, "'" + path + "' names nothing in the job configuration: " + problem);
      return false;
    }
    reference = find_schema_reference(schema_.type_reference(), segments, problem);
    if (reference == nullptr) {
      error(location, "'" + path + "' names nothing in the job configuration: " + problem);
      return false;
    }
    for (const auto& [other_path, other] : claimed_) {
      if (other.first.overlaps(segments)) {
        error(location, "'" + path + "' overlaps '" + other_path + "', already varied at " + other.second);
        return false;
      }
    }
    claimed_.emplace(path, std::make_pair(segments, location));
    return true;
  }

  std::optional<SpecAxis> read_axis(const std::string& path, const nlohmann::json& values, const std::string& location) {
    SpecAxis axis;
    axis.path = path;
    axis.location = location;
    const nlohmann::json* reference = nullptr;
    if (!resolve_path(path, location, axis.segments, reference)) return std::nullopt;
    if (!values.is_array() || values.empty()) {
      error(location, "expected a non-empty list of values");
      return std::nullopt;
    }
    std::vector<CheckedValueProblem> lines;
    for (std::size_t i = 0; i < values.size(); ++i) {
      axis.values.push_back(calc_checked_value(values[i], *reference, location + "[" + std::to_string(i) + "]", lines));
    }
    for (const CheckedValueProblem& line : lines) errors_.push_back(locate_line(file_, document_, line, positions_));
    if (!lines.empty()) return std::nullopt;
    return axis;
  }

  void read_grid(const nlohmann::json& grid, SweepSpec& spec) {
    if (!grid.is_object()) {
      error("sweep.grid", "expected an object {\"dotted.path\": [values...]}");
      return;
    }
    for (const auto& [path, values] : grid.items()) {
      if (auto axis = read_axis(path, values, quoted("sweep.grid", path))) spec.grid.push_back(std::move(*axis));
    }
  }

  void read_zip(const nlohmann::json& zip, SweepSpec& spec) {
    std::vector<nlohmann::json> groups;
    if (zip.is_object()) {
      groups.push_back(zip);
    } else if (zip.is_array()) {
      groups.assign(zip.begin(), zip.end());
    } else {
      error("sweep.zip", "expected a group {\"path\": [...], \"path2\": [...]} or a list of groups");
      return;
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const std::string location = zip.is_object() ? "sweep.zip" : "sweep.zip[" + std::to_string(g) + "]";
      if (!groups[g].is_object() || groups[g].empty()) {
        error(location, "expected a non-empty object {\"dotted.path\": [values...]}");
        continue;
      }
      SpecZipGroup group;
      bool complete = true;
      for (const auto& [path, values] : groups[g].items()) {
        auto axis = read_axis(path, values, quoted(location, path));
        if (axis) {
          group.axes.push_back(std::move(*axis));
        } else {
          complete = false;
        }
      }
      if (!complete) continue;
      for (const SpecAxis& axis : group.axes) {
        if (axis.values.size() != group.axes.front().values.size()) {
          error(location, "lists that vary together must have the same length: " +
                              std::to_string(group.axes.front().values.size()) + " values for '" +
                              group.axes.front().path + "', " + std::to_string(axis.values.size()) + " for '" +
                              axis.path + "'");
          complete = false;
          break;
        }
      }
      if (complete) spec.zip.push_back(std::move(group));
    }
  }

  void read_random(const nlohmann::json& random, SweepSpec& spec) {
    if (!random.is_object()) {
      error("sweep.random", "expected an object {\"samples\": N, \"seed\": S, \"params\": {...}}");
      return;
    }
    check_keys(random, "sweep.random", {"samples", "seed", "params"});
    SpecRandom result;
    if (!random.contains("samples") || !random["samples"].is_number_integer() || random["samples"].get<long long>() < 1 ||
        random["samples"].get<long long>() > 1000000) {
      error("sweep.random.samples", "expected an integer number of samples in [1, 1000000]");
    } else {
      result.samples = random["samples"].get<int>();
    }
    if (random.contains("seed")) {
      if (!random["seed"].is_number_unsigned()) {
        error("sweep.random.seed", "expected a non-negative integer");
      } else {
        result.seed = random["seed"].get<std::uint64_t>();
      }
    }
    if (!random.contains("params") || !random["params"].is_object() || random["params"].empty()) {
      error("sweep.random.params", "expected an object {\"dotted.path\": {\"uniform\": [low, high]}, ...}");
      return;
    }
    const std::vector<std::string> kinds = {"uniform", "loguniform", "choice"};
    for (const auto& [path, distribution] : random["params"].items()) {
      const std::string location = quoted("sweep.random.params", path);
      SpecRandomParam param;
      param.path = path;
      param.location = location;
      const nlohmann::json* reference = nullptr;
      if (!resolve_path(path, location, param.segments, reference)) continue;
      if (!distribution.is_object() || distribution.size() != 1) {
        error(location, "expected one of {\"uniform\": [low, high]}, {\"loguniform\": [low, high]}, {\"choice\": [...]}");
        continue;
      }
      const std::string kind = distribution.begin().key();
      const nlohmann::json& arguments = distribution.begin().value();
      if (kind == "choice") {
        param.distribution = RandomDistribution::choice;
        if (!arguments.is_array() || arguments.empty()) {
          error(location + ".choice", "expected a non-empty list of values");
          continue;
        }
        std::vector<CheckedValueProblem> lines;
        for (std::size_t i = 0; i < arguments.size(); ++i) {
          param.choices.push_back(
              calc_checked_value(arguments[i], *reference, location + ".choice[" + std::to_string(i) + "]", lines));
        }
        for (const CheckedValueProblem& line : lines) errors_.push_back(locate_line(file_, document_, line, positions_));
        if (lines.empty()) result.params.push_back(std::move(param));
        continue;
      }
      if (kind != "uniform" && kind != "loguniform") {
        error(location + "." + kind, "unknown distribution" + make_did_you_mean(kind, kinds));
        continue;
      }
      param.distribution = kind == "uniform" ? RandomDistribution::uniform : RandomDistribution::loguniform;
      if (!reference->is_number_float() && !reference->is_null()) {
        error(location + "." + kind, "draws real numbers, but '" + path + "' is not a real number (use choice)");
        continue;
      }
      if (!arguments.is_array() || arguments.size() != 2 || !arguments[0].is_number() || !arguments[1].is_number()) {
        error(location + "." + kind, "expected [low, high]");
        continue;
      }
      param.low = arguments[0].get<double>();
      param.high = arguments[1].get<double>();
      if (!(param.low <= param.high)) {
        error(location + "." + kind, "low must not exceed high");
        continue;
      }
      if (param.distribution == RandomDistribution::loguniform && !(param.low > 0.0)) {
        error(location + "." + kind, "loguniform needs 0 < low <= high");
        continue;
      }
      result.params.push_back(std::move(param));
    }
    spec.random = std::move(result);
  }

  // An integer member `key` of `object` in [low, high], or `fallback` when absent.
  std::size_t read_count(const nlohmann::json& object, const std::string& location, const std::string& key, long long low,
                         long long high, std::size_t fallback) {
    if (!object.contains(key)) return fallback;
    const nlohmann::json& value = object[key];
    if (!value.is_number_integer() || value.get<long long>() < low || value.get<long long>() > high) {
      error(location + "." + key, "expected an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]");
      return fallback;
    }
    return static_cast<std::size_t>(value.get<long long>());
  }

  void read_search(const nlohmann::json& block, SweepSpec& spec) {
    const std::string at = "sweep.search";
    if (!block.is_object()) {
      error(at, "expected an object {\"method\": ..., \"objective\": {...}, \"space\": {...}, \"budget\": {...}}");
      return;
    }
    check_keys(block, at, {"method", "sampler", "seed", "eta", "slots", "max_trials", "bracket_size", "tpe_startup", "tpe_rule",
                            "objective", "space", "budget", "comment"});
    SpecSearch result;
    search::SearchSettings& settings = result.settings;
    const std::vector<std::string> methods = {"random", "tpe", "asha", "successive_halving", "hyperband"};
    if (!block.contains("method") || !block["method"].is_string()) {
      error(at + ".method", "expected one of \"random\", \"tpe\", \"asha\", \"successive_halving\", \"hyperband\"");
    } else {
      const std::string method = block["method"].get<std::string>();
      const auto found = std::find(methods.begin(), methods.end(), method);
      if (found == methods.end()) {
        error(at + ".method", "unknown method '" + method + "'" + make_did_you_mean(method, methods));
      } else {
        settings.method = static_cast<search::SearchMethod>(found - methods.begin());
      }
    }
    const bool multi_rung = settings.method == search::SearchMethod::asha ||
                            settings.method == search::SearchMethod::successive_halving ||
                            settings.method == search::SearchMethod::hyperband;
    if (block.contains("sampler")) {
      const nlohmann::json& sampler = block["sampler"];
      if (!multi_rung) {
        error(at + ".sampler", "applies to asha, successive_halving and hyperband (tpe and random are samplers themselves)");
      } else if (!sampler.is_string() || (sampler != "random" && sampler != "tpe")) {
        error(at + ".sampler", "expected \"random\" or \"tpe\"");
      } else {
        settings.sampler = sampler == "tpe" ? search::SearchSampler::tpe : search::SearchSampler::random;
      }
    }
    if (block.contains("seed")) {
      if (!block["seed"].is_number_unsigned()) {
        error(at + ".seed", "expected a non-negative integer");
      } else {
        settings.seed = block["seed"].get<std::uint64_t>();
      }
    } else {
      settings.seed = 0;
    }
    settings.eta = read_count(block, at, "eta", 2, 100, settings.eta);
    settings.slots = read_count(block, at, "slots", 1, 1024, settings.slots);
    settings.max_trials = read_count(block, at, "max_trials", 1, 1000000, 0);
    if (block.contains("bracket_size") && settings.method != search::SearchMethod::successive_halving) {
      error(at + ".bracket_size", "applies to successive_halving only");
    }
    settings.bracket_size = read_count(block, at, "bracket_size", 1, 1000000, 0);
    if (block.contains("max_trials") && settings.method != search::SearchMethod::asha &&
        settings.method != search::SearchMethod::random && settings.method != search::SearchMethod::tpe) {
      error(at + ".max_trials", "applies to random, tpe and asha (brackets fix their own sizes)");
    }
    read_search_tpe(block, at, result);
    read_search_budget(block, at, result);
    read_search_objective(block, at, result, multi_rung);
    read_search_space(block, at, result);
    spec.search = std::move(result);
  }

  // The keys of TPE's proposals (method "tpe" or sampler "tpe"): tpe_startup and tpe_rule.
  void read_search_tpe(const nlohmann::json& block, const std::string& at, SpecSearch& result) {
    search::SearchSettings& settings = result.settings;
    const bool tpe = settings.method == search::SearchMethod::tpe || settings.sampler == search::SearchSampler::tpe;
    for (const char* key : {"tpe_startup", "tpe_rule"}) {
      if (block.contains(key) && !tpe) error(at + "." + key, "applies to TPE proposals only (method \"tpe\" or sampler \"tpe\")");
    }
    result.tpe_startup = read_count(block, at, "tpe_startup", 2, 1000000, 0);
    if (!block.contains("tpe_rule") || !tpe) return;
    const nlohmann::json& rule = block["tpe_rule"];
    const std::vector<std::string> rules = {"joint", "per_axis"};
    if (!rule.is_string() || std::find(rules.begin(), rules.end(), rule.get<std::string>()) == rules.end()) {
      const std::string text = rule.is_string() ? "'" + rule.get<std::string>() + "'" : rule.dump();
      error(at + ".tpe_rule", "expected \"joint\" (the default) or \"per_axis\", not " + text +
                                  (rule.is_string() ? make_did_you_mean(rule.get<std::string>(), rules) : ""));
      return;
    }
    settings.tpe.joint = rule == "joint";
    result.tpe_rule_given = true;
  }

  void read_search_budget(const nlohmann::json& block, const std::string& at, SpecSearch& result) {
    const std::string location = at + ".budget";
    if (!block.contains("budget")) {
      error(location, "missing; give {\"jobs\": N} or {\"cpu_seconds\": S}");
      return;
    }
    const nlohmann::json& budget = block["budget"];
    if (!budget.is_object() || budget.size() != 1 || (!budget.contains("jobs") && !budget.contains("cpu_seconds"))) {
      if (budget.is_object()) check_keys(budget, location, {"jobs", "cpu_seconds"});
      error(location, "expected {\"jobs\": N} or {\"cpu_seconds\": S}");
      return;
    }
    if (budget.contains("jobs")) {
      result.budget_unit = SpecSearch::BudgetUnit::jobs;
      result.budget = static_cast<double>(read_count(budget, location, "jobs", 1, 10000000, 0));
      return;
    }
    result.budget_unit = SpecSearch::BudgetUnit::cpu_seconds;
    const nlohmann::json& seconds = budget["cpu_seconds"];
    if (!seconds.is_number() || !(seconds.get<double>() > 0.0) || !std::isfinite(seconds.get<double>())) {
      error(location + ".cpu_seconds", "expected a positive number of CPU-seconds");
      return;
    }
    result.budget = seconds.get<double>();
  }

  // sweep.search.objective: its metric, joint and checkpoint, and from them the rungs and the key
  // that ends a short rung's learning.
  void read_search_objective(const nlohmann::json& block, const std::string& at, SpecSearch& result, bool multi_rung) {
    const std::string location = at + ".objective";
    if (!block.contains("objective") || !block["objective"].is_object()) {
      error(location, "expected {\"metric\": NAME, \"joint\": N or \"mean\", \"checkpoint\": N or \"last\"}");
      return;
    }
    const nlohmann::json& objective = block["objective"];
    check_keys(objective, location, {"metric", "joint", "checkpoint"});
    const MetricInfo* info = read_objective_metric(objective, location);
    if (info == nullptr) return;
    result.objective.metric = info->name;
    result.objective.lower_is_better = info->direction == MetricDirection::lower;
    read_objective_joint(objective, location, *info, result);
    if (!read_search_rungs(objective, location, *info, result, multi_rung)) return;
    set_rung_length_key(result, multi_rung);
  }

  // The objective's metric: a result metric of the catalog with a direction; null when refused.
  const MetricInfo* read_objective_metric(const nlohmann::json& objective, const std::string& location) {
    if (!objective.contains("metric") || !objective["metric"].is_string()) {
      error(location + ".metric", "expected the name of a result metric of the catalog");
      return nullptr;
    }
    const std::string name = objective["metric"].get<std::string>();
    std::vector<std::string> names;
    for (const MetricInfo& info : metric_catalog()) names.push_back(info.name);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      error(location + ".metric", "'" + name + "' is not a metric of the catalog" + make_did_you_mean(name, names));
      return nullptr;
    }
    const MetricInfo& info = find_metric_info(name);
    if (info.direction == MetricDirection::none) {
      error(location + ".metric", "'" + name + "' has no direction of better in the catalog: a search cannot optimise it");
      return nullptr;
    }
    if (info.kind != MetricKind::result) {
      error(location + ".metric", "'" + name + "' is a " + to_string(info.kind) + " metric, not a result: it varies run to run");
      return nullptr;
    }
    return &info;
  }

  // objective.joint: a 1-based joint or "mean" (0, the default), for a per-joint metric only.
  void read_objective_joint(const nlohmann::json& objective, const std::string& location, const MetricInfo& info,
                            SpecSearch& result) {
    if (!objective.contains("joint")) return;
    const nlohmann::json& joint = objective["joint"];
    const bool per_joint = info.scope == MetricScope::joint || info.scope == MetricScope::checkpoint;
    if (!per_joint) {
      error(location + ".joint", "'" + info.name + "' is a " + to_string(info.scope) + " metric, not one per joint");
    } else if (joint == "mean") {
      result.objective.joint = 0;
    } else if (!joint.is_number_integer() || joint.get<long long>() < 1 || joint.get<long long>() > 1000) {
      error(location + ".joint", "expected a 1-based joint number or \"mean\"");
    } else {
      result.objective.joint = joint.get<int>();
    }
  }

  // The base's learning.heldout_checkpoints as integers (empty when it sets none).
  std::vector<std::int64_t> find_heldout_checkpoints() const {
    std::vector<std::int64_t> checkpoints;
    if (resolved_.contains("learning") && resolved_["learning"].contains("heldout_checkpoints")) {
      for (const nlohmann::json& c : resolved_["learning"]["heldout_checkpoints"]) {
        // The list's elements may be stored as reals (an empty default list means "numbers").
        if (c.is_number() && c.get<double>() == std::floor(c.get<double>())) checkpoints.push_back(static_cast<std::int64_t>(c.get<double>()));
      }
    }
    return checkpoints;
  }

  // The rungs: the checkpoints up to objective.checkpoint (default the last). A metric without
  // checkpoints, or a base without them, has one rung (the whole job). False when the rungs end
  // there (one rung, or a refused checkpoint): no rung is short, so no length key.
  bool read_search_rungs(const nlohmann::json& objective, const std::string& location, const MetricInfo& info,
                         SpecSearch& result, bool multi_rung) {
    const std::string& name = info.name;
    const std::vector<std::int64_t> checkpoints = find_heldout_checkpoints();
    if (info.scope != MetricScope::checkpoint) {
      if (objective.contains("checkpoint")) {
        error(location + ".checkpoint", "'" + name + "' is not measured at checkpoints");
      }
      if (multi_rung) {
        error(location + ".metric", "successive halving needs an objective measured at learning checkpoints (heldout_*), not '" + name + "'");
      }
      result.rungs = {0};
      return false;
    }
    if (checkpoints.empty()) {
      if (multi_rung) {
        error(location + ".checkpoint", "successive halving needs learning.heldout_checkpoints in base (its rungs)");
      }
      if (objective.contains("checkpoint") && objective["checkpoint"] != "last") {
        error(location + ".checkpoint", "base sets no learning.heldout_checkpoints: only \"last\" exists");
      }
      result.rungs = {0};
      return false;
    }
    std::size_t last = checkpoints.size() - 1;
    if (objective.contains("checkpoint") && objective["checkpoint"] != "last") {
      const nlohmann::json& wanted = objective["checkpoint"];
      const auto found = wanted.is_number_integer()
                             ? std::find(checkpoints.begin(), checkpoints.end(), wanted.get<std::int64_t>())
                             : checkpoints.end();
      if (found == checkpoints.end()) {
        error(location + ".checkpoint", "expected \"last\" or one of learning.heldout_checkpoints " + nlohmann::json(checkpoints).dump());
        return false;
      }
      last = static_cast<std::size_t>(found - checkpoints.begin());
    }
    result.objective.checkpoint = checkpoints[last];
    result.checkpoint_segments = parse_config_path("learning.heldout_checkpoints");
    result.rungs.assign(checkpoints.begin(), checkpoints.begin() + static_cast<std::ptrdiff_t>(last + 1));
    if (multi_rung && result.rungs.size() < 2) {
      error(location + ".checkpoint", "successive halving needs at least two checkpoints up to the objective's");
    }
    return true;
  }

  // The key that ends a step's learning at its rung (SpecSearch::length_path).
  void set_rung_length_key(SpecSearch& result, bool multi_rung) {
    const std::string mode = resolved_["learning"].value("mode", "");
    const std::string trajectory = resolved_.contains("trajectory") ? resolved_["trajectory"].value("kind", "") : "";
    if (multi_rung && mode == "batch") result.length_path = "learning.epochs";
    if (multi_rung && mode == "online" && trajectory == "reaching") result.length_path = "trajectory.reaching.reaches";
    if (!result.length_path.empty()) result.length_segments = parse_config_path(result.length_path);
  }

  // A search axis may not vary a key that each step already sets: learning.heldout_checkpoints
  // (the checkpoints up to the step's rung) or the length key of a rung's job (learning.epochs,
  // trajectory.reaching.reaches: the rung's checkpoint). Such an axis would give two values to
  // one key, so it is refused rather than given a meaning.
  bool check_not_set_by_rungs(const std::string& path, const std::string& where, const ConfigPath& segments,
                              const SpecSearch& result) {
    const auto overlaps = [&](const ConfigPath& set) { return !set.empty() && set.overlaps(segments); };
    if (overlaps(result.length_segments)) {
      error(where, "'" + path + "' is set by the search: a step to a rung runs " + result.length_path +
                       " up to that rung's checkpoint (learning.heldout_checkpoints are the rungs), so it cannot be an axis too");
      return false;
    }
    if (overlaps(result.checkpoint_segments)) {
      error(where, "'" + path + "' is set by the search: each step runs the held-out checkpoints up to its rung (the objective's checkpoint), so it cannot be an axis too");
      return false;
    }
    return true;
  }

  void read_search_space(const nlohmann::json& block, const std::string& at, SpecSearch& result) {
    const std::string location = at + ".space";
    if (!block.contains("space") || !block["space"].is_object() || block["space"].empty()) {
      error(location, "expected an object {\"dotted.path\": {\"uniform\": [low, high]}, ...}");
      return;
    }
    const std::vector<std::string> kinds = {"uniform", "log_uniform", "integer", "categorical"};
    for (const auto& [path, distribution] : block["space"].items()) {
      const std::string where = quoted(location, path);
      SpecSearchAxis axis;
      axis.location = where;
      search::SearchAxis sampled;
      sampled.path = path;
      const nlohmann::json* reference = nullptr;
      if (!resolve_path(path, where, axis.segments, reference)) continue;
      if (!check_not_set_by_rungs(path, where, axis.segments, result)) continue;
      if (!distribution.is_object() || distribution.size() != 1) {
        error(where, "expected one of {\"uniform\": [low, high]}, {\"log_uniform\": [low, high]}, {\"integer\": [low, high]}, {\"categorical\": [...]}");
        continue;
      }
      const std::string kind = distribution.begin().key();
      const nlohmann::json& arguments = distribution.begin().value();
      const auto found = std::find(kinds.begin(), kinds.end(), kind);
      if (found == kinds.end()) {
        error(where + "." + kind, "unknown distribution" + make_did_you_mean(kind, kinds));
        continue;
      }
      sampled.kind = static_cast<search::AxisKind>(found - kinds.begin());
      if (sampled.kind == search::AxisKind::categorical) {
        if (!arguments.is_array() || arguments.size() < 2) {
          error(where + ".categorical", "expected a list of at least two values");
          continue;
        }
        std::vector<CheckedValueProblem> lines;
        for (std::size_t i = 0; i < arguments.size(); ++i) {
          axis.choices.push_back(calc_checked_value(arguments[i], *reference, where + ".categorical[" + std::to_string(i) + "]", lines));
        }
        for (const CheckedValueProblem& line : lines) errors_.push_back(locate_line(file_, document_, line, positions_));
        if (!lines.empty()) continue;
        sampled.choice_count = axis.choices.size();
      } else {
        const std::string here = where + "." + kind;
        const bool integer = sampled.kind == search::AxisKind::integer;
        if (integer ? !(reference->is_number_integer() || reference->is_null()) : !(reference->is_number_float() || reference->is_null())) {
          error(here, "draws " + std::string(integer ? "integers" : "real numbers") + ", but '" + path + "' is " +
                          (integer ? "not an integer" : "not a real number") + " (use categorical)");
          continue;
        }
        if (!arguments.is_array() || arguments.size() != 2 || !arguments[0].is_number() || !arguments[1].is_number() ||
            (integer && (!arguments[0].is_number_integer() || !arguments[1].is_number_integer()))) {
          error(here, integer ? "expected [low, high], whole numbers" : "expected [low, high]");
          continue;
        }
        sampled.low = arguments[0].get<double>();
        sampled.high = arguments[1].get<double>();
        if (!std::isfinite(sampled.low) || !std::isfinite(sampled.high) || !(sampled.low < sampled.high)) {
          error(here, "empty range [" + arguments[0].dump() + ", " + arguments[1].dump() + "]: low must be below high");
          continue;
        }
        if (sampled.kind == search::AxisKind::log_uniform && !(sampled.low > 0.0)) {
          error(here, "log_uniform needs 0 < low < high");
          continue;
        }
        if (schema_.find_key_range) {
          if (const std::optional<Range> range = schema_.find_key_range(path)) {
            if (!range->contains(sampled.low) || !range->contains(sampled.high)) {
              error(here, "[" + arguments[0].dump() + ", " + arguments[1].dump() + "] leaves the key's range " + range->describe());
              continue;
            }
          }
        }
      }
      result.settings.space.axes.push_back(sampled);
      result.axes.push_back(std::move(axis));
    }
  }

  // "" when `value` (a JSON integer) is a seed the 'seed' key's range allows (its one home: the
  // key table, engine/experiment/job_config.cpp), else why not. Read exactly: a uint64 above
  // 2^63 - 1 is never cast to a negative int64.
  static std::string check_seed(const nlohmann::json& value, std::int64_t& seed) {
    static const Range range = [] {
      for (const JobConfigKey& key : job_config_keys()) {
        if (key.path == "seed") return key.range;
      }
      return Range{};
    }();
    const std::string problem = "seed " + value.dump() + " is outside the seed range " + range.describe();
    if (value.is_number_unsigned()) {
      const auto number = value.get<std::uint64_t>();
      if (number > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return problem;
    }
    seed = value.get<std::int64_t>();
    return range.contains(static_cast<double>(seed)) ? "" : problem;
  }

  void read_repeat(const nlohmann::json& repeat, SweepSpec& spec) {
    ConfigPath segments;
    const nlohmann::json* reference = nullptr;
    if (!resolve_path("seed", "sweep.repeat", segments, reference)) return;
    if (!resolved_["seed"].is_number_integer()) {
      error("sweep.repeat", "the job configuration's 'seed' is not an integer");
      return;
    }
    if (repeat.is_number_integer()) {
      const long long count = repeat.get<long long>();
      if (count < 1 || count > 100000) {
        error("sweep.repeat", "expected a number of repeats in [1, 100000] or a list of seeds");
        return;
      }
      std::int64_t first = 0;
      if (const std::string problem = check_seed(resolved_["seed"], first); !problem.empty()) {
        error("sweep.repeat", "the job configuration's " + problem);
        return;
      }
      std::int64_t last = 0;
      if (const std::string problem = check_seed(nlohmann::json(first + (count - 1)), last); !problem.empty()) {
        error("sweep.repeat", std::to_string(count) + " repeats from seed " + std::to_string(first) + " reach past the seed range");
        return;
      }
      for (long long i = 0; i < count; ++i) spec.repeat_seeds.push_back(first + i);
      return;
    }
    if (!repeat.is_array() || repeat.empty()) {
      error("sweep.repeat", "expected a number of repeats or a non-empty list of integer seeds");
      return;
    }
    std::set<std::int64_t> seen;
    for (std::size_t i = 0; i < repeat.size(); ++i) {
      if (!repeat[i].is_number_integer()) {
        error("sweep.repeat[" + std::to_string(i) + "]", "expected an integer seed");
        continue;
      }
      std::int64_t seed = 0;
      if (const std::string problem = check_seed(repeat[i], seed); !problem.empty()) {
        error("sweep.repeat[" + std::to_string(i) + "]", problem);
        continue;
      }
      if (!seen.insert(seed).second) {
        error("sweep.repeat[" + std::to_string(i) + "]", "seed " + std::to_string(seed) + " is repeated");
        continue;
      }
      spec.repeat_seeds.push_back(seed);
    }
  }

  const std::string& file_;
  const std::string& folder_;
  const JobConfigSchema& schema_;
  const SpecPositions positions_;
  JsonDocument document_;
  nlohmann::json resolved_;
  std::vector<SpecInclude> includes_;
  std::map<std::string, std::string> input_folders_;  // field → folder of the include that set it
  std::map<std::string, std::string> input_writers_;  // field → that include's file
  std::map<std::string, std::string> writers_;        // the same, for fields this spec does not set
  std::vector<std::string> errors_;
  std::map<std::string, std::pair<ConfigPath, std::string>> claimed_;
};

}  // namespace

nlohmann::json calc_search_step_params(const SpecSearch& search, const search::SearchPoint& point, std::size_t rung) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t d = 0; d < search.axes.size(); ++d) {
    const search::SearchAxis& axis = search.settings.space.axes[d];
    switch (axis.kind) {
      case search::AxisKind::uniform:
      case search::AxisKind::log_uniform: params[axis.path] = point[d]; break;
      case search::AxisKind::integer: params[axis.path] = static_cast<std::int64_t>(point[d]); break;
      case search::AxisKind::categorical: params[axis.path] = search.axes[d].choices[static_cast<std::size_t>(point[d])]; break;
    }
  }
  if (search.objective.checkpoint) {
    params["learning.heldout_checkpoints"] =
        std::vector<std::int64_t>(search.rungs.begin(), search.rungs.begin() + static_cast<std::ptrdiff_t>(rung + 1));
  }
  // Below the last rung, learning ends at the rung's checkpoint (the last rung is the job as the
  // base defines it, so its key is the one a random or TPE search of the same point has).
  if (!search.length_path.empty() && rung + 1 < search.rungs.size() && search.rungs[rung] > 0) {
    params[search.length_path] = search.rungs[rung];
  }
  return params;
}

search::SearchHistory calc_initial_search_steps(const SpecSearch& search) {
  search::SearchSettings settings = search.settings;
  settings.rung_cost.assign(search.rungs.size(), 1.0);  // costs do not change which steps come first
  search::SearchHistory history;
  for (;;) {
    const search::NextStep next = search::calc_next_step(settings, history);
    if (next.needs_loss || next.decision.kind != search::SearchDecision::Kind::run) return history;
    search::add_step(next.decision, next.visible, history);
  }
}

SweepSpec parse_sweep_spec(const std::string& text, const std::string& file, const std::string& folder,
                           const JobConfigSchema& schema) {
  return SpecParser(file, folder, schema, SpecPositions::given).parse(text);
}

SweepSpec parse_sweep_spec(const std::string& text, const std::string& file, const std::string& folder,
                           const JobConfigSchema& schema, SpecPositions positions) {
  return SpecParser(file, folder, schema, positions).parse(text);
}

SweepSpec load_sweep_spec(const std::string& path, const JobConfigSchema& schema) {
  const std::string text = read_text_file(path, "");
  const std::string folder = std::filesystem::path(path).parent_path().string();
  return parse_sweep_spec(text, path, folder.empty() ? "." : folder, schema);
}

}  // namespace armfarm
