// sweeps/README.md's job-configuration table and the engine's key tables describe the same
// keys, with the same defaults (as the JSON defaults tree writes them), units and ranges. On a
// mismatch the test prints the table the code implies, to paste into the README.
#include "runner/config/job_config_json.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace armfarm {
namespace {

struct DocRow {
  std::string default_value, unit, allowed;
};

std::string strip(const std::string& text) {
  const auto begin = text.find_first_not_of(' ');
  const auto end = text.find_last_not_of(' ');
  return begin == std::string::npos ? "" : text.substr(begin, end - begin + 1);
}

std::string unquote(const std::string& cell) {
  const std::string s = strip(cell);
  return s.size() >= 2 && s.front() == '`' && s.back() == '`' ? s.substr(1, s.size() - 2) : s;
}

/// Rows "| `key` | `default` | unit | allowed | meaning |" of the README's job configuration section.
std::map<std::string, DocRow> read_documented_keys() {
  std::ifstream file(std::string(ARMFARM_SOURCE_DIR) + "/sweeps/README.md");
  std::map<std::string, DocRow> rows;
  bool in_section = false;
  for (std::string line; std::getline(file, line);) {
    if (line.rfind("## ", 0) == 0) in_section = line == "## The job configuration";
    if (!in_section || line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream stream(line.substr(1));
    for (std::string cell; std::getline(stream, cell, '|');) cells.push_back(cell);
    if (cells.size() < 5) continue;
    rows[unquote(cells[0])] = {unquote(cells[1]), strip(cells[2]), strip(cells[3])};
  }
  return rows;
}

std::string describe_allowed(const JobConfigKey& key, const FieldRef& field) {
  std::string text;
  switch (field.kind) {
    case ValueKind::choice:
      for (const EnumName& name : *field.choices) text += (text.empty() ? "" : ", ") + std::string("`\"") + name.name + "\"`";
      return text;
    case ValueKind::boolean: return "true, false";
    case ValueKind::text: return key.path == "end_effector.link" ? "a link of the model" : "a path";
    case ValueKind::name_list: return "names listed";
    case ValueKind::integer: return key.range.describe() + ", integer";
    case ValueKind::integer_or_auto: return key.range.describe() + ", integer, or `\"auto\"`";
    case ValueKind::real_or_auto: return key.range.describe() + " or `\"auto\"`";
    case ValueKind::point_or_auto: return key.range.describe() + " each, or `\"auto\"`";
    case ValueKind::integer_list:
      return key.size == ListSize::joint_numbers ? "joints 1..n, each once" : key.range.describe() + " each, integers";
    case ValueKind::point: return key.range.describe() + " each";
    case ValueKind::real_matrix: return key.range.describe() + " each, or SPD";
    case ValueKind::real_list:
    case ValueKind::real_or_list:
      if (key.size == ListSize::movable_joints) return "within each joint's limits; 0 or one per joint";
      text = key.range.describe() + " each";
      if (key.size == ListSize::per_joint) text += "; 0, 1 or n";
      if (key.size == ListSize::lwpr_inputs) text += "; 1 or 3n";
      if (key.size == ListSize::lwpr_outputs) text += "; 1 or n";
      return text;
    case ValueKind::real: return key.range.describe();
  }
  return text;
}

const nlohmann::json& find_default(const nlohmann::json& tree, const std::string& path) {
  const nlohmann::json* node = &tree;
  std::stringstream stream(path);
  for (std::string part; std::getline(stream, part, '.');) node = &node->at(part);
  return *node;
}

TEST(JobConfigDocs, EveryKeyIsDocumentedWithItsDefaultUnitAndRange) {
  const std::map<std::string, DocRow> documented = read_documented_keys();
  const nlohmann::json defaults = make_job_config_defaults();
  std::map<std::string, DocRow> expected;
  std::string table;
  for (const RunnerConfigKey& key : runner_config_keys()) {
    expected[key.path] = {nlohmann::json(key.default_value).dump(), "", "a path"};
    table += "| `" + std::string(key.path) + "` | `" + expected[key.path].default_value + "` |  | a path | " + key.doc + " |\n";
  }
  JobConfig config;
  for (const JobConfigKey& key : job_config_keys()) {
    const DocRow row{find_default(defaults, key.path).dump(), key.unit, describe_allowed(key, key.field(config))};
    expected[key.path] = row;
    table += "| `" + key.path + "` | `" + row.default_value + "` | " + row.unit + " | " + row.allowed + " | " + key.doc + " |\n";
  }
  bool same = !documented.empty();
  EXPECT_FALSE(documented.empty()) << "no job configuration table found in sweeps/README.md";
  for (const auto& [path, row] : documented.empty() ? decltype(expected){} : expected) {
    const auto found = documented.find(path);
    if (found == documented.end()) {
      ADD_FAILURE() << path << " is a key but sweeps/README.md does not document it";
      same = false;
      continue;
    }
    EXPECT_EQ(found->second.default_value, row.default_value) << path << ": default";
    EXPECT_EQ(found->second.unit, row.unit) << path << ": unit";
    EXPECT_EQ(found->second.allowed, row.allowed) << path << ": allowed values";
    same = same && found->second.default_value == row.default_value && found->second.unit == row.unit &&
           found->second.allowed == row.allowed;
  }
  for (const auto& [path, row] : documented) {
    if (!expected.count(path)) {
      ADD_FAILURE() << "sweeps/README.md documents " << path << ", which is no key";
      same = false;
    }
  }
  if (!same) std::cout << "The table the code implies:\n" << table;
}

}  // namespace
}  // namespace armfarm
