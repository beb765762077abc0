#include "runner/spec/sweep_stages.hpp"

#include "engine/io/input_file.hpp"
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_spec_positions.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>

namespace armfarm {
namespace {

// `over` merged into `into`: objects key by key, anything else replaced.
void merge_json(nlohmann::json& into, const nlohmann::json& over) {
  if (!into.is_object() || !over.is_object()) {
    into = over;
    return;
  }
  for (const auto& [key, value] : over.items()) merge_json(into[key], value);
}

// Replaces every {"stage": S[, "params": P]} inside `node` by {"sweep": "<name>.S"[, "params": P]};
// S must be one of `earlier`. Problems go to `errors` with `where`.
void rewrite_stage_references(nlohmann::json& node, const std::string& name, const std::set<std::string>& earlier,
                              const std::string& where, std::vector<std::string>& errors) {
  if (node.is_array()) {
    for (nlohmann::json& element : node) rewrite_stage_references(element, name, earlier, where, errors);
    return;
  }
  if (!node.is_object()) return;
  const bool reference = node.contains("stage") && std::all_of(node.items().begin(), node.items().end(), [](const auto& item) {
                           return item.key() == "stage" || item.key() == "params";
                         });
  if (!reference) {
    for (auto& [key, value] : node.items()) rewrite_stage_references(value, name, earlier, where, errors);
    return;
  }
  if (!node["stage"].is_string() || earlier.count(node["stage"].get<std::string>()) == 0) {
    errors.push_back(where + ": " + node.dump() + ": \"stage\" names an earlier stage (" +
                     (earlier.empty() ? std::string("this is the first stage") : "one of " + nlohmann::json(earlier).dump()) + ")");
    return;
  }
  nlohmann::json replaced = {{"sweep", name + "." + node["stage"].get<std::string>()}};
  if (node.contains("params")) replaced["params"] = node["params"];
  node = std::move(replaced);
}

bool is_stage_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

}  // namespace

std::vector<SweepSpec> parse_sweep_stages(const std::string& text, const std::string& file, const std::string& folder,
                                          const JobConfigSchema& schema) {
  const JsonDocument document = parse_json_document(text, file);
  const nlohmann::json& root = document.value;
  if (!root.is_object() || !root.contains("stages")) return {parse_sweep_spec(text, file, folder, schema)};

  std::vector<std::string> errors;
  for (const auto& [key, value] : root.items()) {
    if (key != "name" && key != "description" && key != "include" && key != "base" && key != "stages" && key != "comment") {
      errors.push_back(file + ": " + key + ": unknown key of a staged spec (name, description, include, base, stages, comment; "
                                          "a stage's sweep goes in the stage)");
    }
  }
  if (!root.contains("name") || !root["name"].is_string() || root["name"].get<std::string>().empty()) {
    errors.push_back(file + ": name: missing or not a non-empty string; every sweep needs a name");
  }
  const nlohmann::json& stages = root["stages"];
  if (!stages.is_array() || stages.empty()) errors.push_back(file + ": stages: expected a non-empty list of stage objects");
  if (!errors.empty()) throw SpecError(errors);

  const std::string name = root["name"].get<std::string>();
  std::set<std::string> earlier;
  std::vector<nlohmann::json> documents;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const std::string where = file + ": stages[" + std::to_string(i) + "]";
    const nlohmann::json& stage = stages[i];
    if (!stage.is_object()) {
      errors.push_back(where + ": expected an object with name, description, base and sweep");
      continue;
    }
    for (const auto& [key, value] : stage.items()) {
      if (key != "name" && key != "description" && key != "base" && key != "sweep" && key != "comment") {
        errors.push_back(where + "." + key + ": unknown key of a stage (name, description, base, sweep, comment)");
      }
    }
    const std::string stage_name = stage.value("name", nlohmann::json()).is_string() ? stage["name"].get<std::string>() : "";
    if (!is_stage_name(stage_name)) {
      errors.push_back(where + ".name: expected a name of letters, digits, _ and -");
      continue;
    }
    if (earlier.count(stage_name)) {
      errors.push_back(where + ".name: \"" + stage_name + "\" names an earlier stage too");
      continue;
    }
    nlohmann::json doc = {{"name", name + "." + stage_name}};
    std::string description = root.value("description", std::string());
    if (stage.contains("description") && stage["description"].is_string()) {
      description += (description.empty() ? "" : " Stage ") + stage_name + ": " + stage["description"].get<std::string>();
    }
    doc["description"] = description;
    if (root.contains("include")) doc["include"] = root["include"];
    nlohmann::json base = root.value("base", nlohmann::json::object());
    if (stage.contains("base")) merge_json(base, stage["base"]);
    doc["base"] = std::move(base);
    if (stage.contains("sweep")) doc["sweep"] = stage["sweep"];
    rewrite_stage_references(doc["base"], name, earlier, where + " (" + stage_name + ")", errors);
    if (doc.contains("sweep")) rewrite_stage_references(doc["sweep"], name, earlier, where + " (" + stage_name + ")", errors);
    earlier.insert(stage_name);
    documents.push_back(std::move(doc));
  }
  if (!errors.empty()) throw SpecError(errors);

  // Each stage is checked as a sweep of its own; its messages name the stage (positions would
  // point into the merged document, so the parser gives none).
  std::vector<SweepSpec> specs;
  for (std::size_t i = 0; i < documents.size(); ++i) {
    const std::string stage_file = file + ": stages[" + std::to_string(i) + "] (" + stages[i]["name"].get<std::string>() +
                                   ", merged with the top-level base)";
    try {
      SweepSpec spec = parse_sweep_spec(documents[i].dump(2), stage_file, folder, schema, SpecPositions::omitted);
      spec.text = text;
      specs.push_back(std::move(spec));
    } catch (const SpecError& error) {
      errors.insert(errors.end(), error.lines().begin(), error.lines().end());
    }
  }
  if (!errors.empty()) throw SpecError(errors);
  return specs;
}

std::vector<SweepSpec> load_sweep_stages(const std::string& path, const JobConfigSchema& schema) {
  if (std::filesystem::is_directory(path)) throw SpecError({path + ": is a directory, not a sweep spec"});
  std::string text;
  try {
    text = read_input_file(path, InputFileKind::json);
  } catch (const InputFileError& error) {
    throw SpecError({error.what()});
  }
  const JsonDocument document = parse_json_document(text, path);
  if (!document.value.is_object() || !document.value.contains("stages")) return {load_sweep_spec(path, schema)};
  std::string folder = std::filesystem::path(path).parent_path().string();
  return parse_sweep_stages(text, path, folder.empty() ? "." : folder, schema);
}

}  // namespace armfarm
