#include "runner/execution/input_changes.hpp"

#include "results/results_store.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_path.hpp"

#include <filesystem>
#include <set>

namespace armfarm {
namespace {

// Names of the file inputs `config` records.
std::set<std::string> find_file_inputs(const nlohmann::json& config) {
  std::set<std::string> names;
  if (config.contains("inputs") && config["inputs"].is_object()) {
    for (const auto& [name, entry] : config["inputs"].items()) {
      if (entry.is_object() && entry.value("kind", "file") == "file") names.insert(name);
    }
  }
  return names;
}

// `config` without inputs and with the named fields blanked.
std::string calc_text_without(const nlohmann::json& config, const std::set<std::string>& fields) {
  nlohmann::json stripped = config;
  stripped.erase("inputs");
  for (const std::string& field : fields) {
    std::string problem;
    ConfigPath segments;
    try {
      segments = parse_config_path(field);
    } catch (const std::invalid_argument&) {
      continue;
    }
    if (find_config_element(stripped, segments, problem) != nullptr) set_config_element(stripped, segments, "");
  }
  return calc_canonical_json(stripped);
}

std::string find_hash(const nlohmann::json& config, const std::string& name) {
  if (!config.contains("inputs") || !config["inputs"].contains(name)) return "";
  return config["inputs"][name].value("hash", "");
}

}  // namespace

InputChangeReport find_input_changes(const ExpandedSweep& sweep, const std::string& db_path) {
  InputChangeReport report;
  if (!std::filesystem::exists(db_path)) return report;
  try {
    const ResultsStore store = ResultsStore::open(db_path, ResultsStore::Mode::read_only);
    std::multimap<std::string, JobRecord> stored_by_params;
    std::set<std::string> stored_keys;
    for (JobRecord& job : store.find_jobs(sweep.spec.name)) {
      stored_keys.insert(job.key);
      stored_by_params.emplace(calc_canonical_json(job.params), std::move(job));
    }
    for (const ExpandedJob& job : sweep.jobs) {
      if (stored_keys.count(job.key) != 0 || store.find_job(job.key)) continue;
      const auto [first, last] = stored_by_params.equal_range(calc_canonical_json(job.params));
      for (auto it = first; it != last; ++it) {
        const nlohmann::json& old = it->second.config;
        const nlohmann::json config = job.config();
        std::set<std::string> fields = find_file_inputs(config);
        const std::set<std::string> old_fields = find_file_inputs(old);
        fields.insert(old_fields.begin(), old_fields.end());
        if (calc_text_without(old, fields) != calc_text_without(config, fields)) continue;
        ++report.changed;
        std::set<std::string> names;
        for (const auto& either : {config, old}) {
          if (either.contains("inputs") && either["inputs"].is_object()) {
            for (const auto& item : either["inputs"].items()) names.insert(item.key());
          }
        }
        for (const std::string& name : names) {
          if (find_hash(config, name) != find_hash(old, name)) ++report.inputs[name];
        }
        break;
      }
    }
  } catch (const std::exception&) {
    return InputChangeReport{};
  }
  return report;
}

std::string make_input_change_text(const InputChangeReport& report) {
  if (report.changed == 0) return "";
  std::string text = std::to_string(report.changed) + (report.changed == 1 ? " job is" : " jobs are") +
                     " new because an input file changed (";
  bool first = true;
  for (const auto& [name, count] : report.inputs) {
    text += (first ? "" : ", ") + name + ": " + std::to_string(count);
    first = false;
  }
  return text + ")";
}

}  // namespace armfarm
