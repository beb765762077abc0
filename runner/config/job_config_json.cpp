#include "runner/config/job_config_json.hpp"

#include "engine/experiment/job_config_validation.hpp"
#include "engine/io/input_file.hpp"
#include "runner/config/config_error.hpp"
#include "runner/config/config_value_json.hpp"
#include "runner/io/csv_reader.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/input_files.hpp"

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace armfarm {
namespace {

using nlohmann::json;

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string::size_type start = 0;
  for (auto dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
    parts.push_back(path.substr(start, dot - start));
    start = dot + 1;
  }
  parts.push_back(path.substr(start));
  return parts;
}

/// The value at a dotted path, nullptr when absent (no allocation: it runs for every key of
/// every job a sweep expands).
const json* find_value(const json& root, const std::string& path) {
  const json* node = &root;
  std::string_view rest = path;
  while (true) {
    const std::size_t dot = rest.find('.');
    const std::string_view part = rest.substr(0, dot);
    if (!node->is_object()) return nullptr;
    const auto found = node->find(part);
    if (found == node->end()) return nullptr;
    node = &*found;
    if (dot == std::string_view::npos) return node;
    rest.remove_prefix(dot + 1);
  }
}

/// find_value for keys read in table order: keys of one parent object follow each other
/// (learning.lwpr.*), so the parent found for the last key is reused.
class ValueFinder {
 public:
  explicit ValueFinder(const json& root) : root_(root) {}
  const json* find(const std::string& path) {
    const std::size_t dot = path.rfind('.');
    if (dot == std::string::npos) return find_value(root_, path);
    const std::string_view parent(path.data(), dot);
    if (parent != parent_path_ || !have_parent_) {
      parent_ = find_value(root_, std::string(parent));
      parent_path_ = parent;
      have_parent_ = true;
    }
    if (parent_ == nullptr || !parent_->is_object()) return nullptr;
    const auto found = parent_->find(std::string_view(path).substr(dot + 1));
    return found == parent_->end() ? nullptr : &*found;
  }

 private:
  const json& root_;
  std::string_view parent_path_;  // views a key's path in job_config_keys()
  const json* parent_ = nullptr;
  bool have_parent_ = false;
};

void set_value(json& root, const std::string& path, json value) {
  json* node = &root;
  for (const std::string& part : split_path(path)) node = &(*node)[part];
  *node = std::move(value);
}

}  // namespace

const std::vector<RunnerConfigKey>& runner_config_keys() {
  static const std::vector<RunnerConfigKey> keys = {
      {"model", "models/dlr_lwr3.urdf", "arm description (URDF or DCG); a relative path resolves against the file that wrote it, the default against the data directory"},
  };
  return keys;
}

nlohmann::json make_job_config_defaults() {
  JobConfig defaults;
  json tree = json::object();
  for (const RunnerConfigKey& key : runner_config_keys()) set_value(tree, key.path, key.default_value);
  for (const JobConfigKey& key : job_config_keys()) set_value(tree, key.path, make_field_json(key.field(defaults)));
  return tree;
}

nlohmann::json make_job_config_types() {
  JobConfig defaults;
  json tree = make_job_config_defaults();
  for (const JobConfigKey& key : job_config_keys()) {
    const ValueKind kind = key.field(defaults).kind;
    if (kind == ValueKind::real_or_list || kind == ValueKind::real_matrix || kind == ValueKind::integer_or_auto ||
        kind == ValueKind::real_or_auto || kind == ValueKind::point_or_auto) {
      set_value(tree, key.path, nullptr);
    }
  }
  // A model file path or a stored-model reference object, resolved when the sweep expands.
  set_value(tree, "learning.initial_model", nullptr);
  return tree;
}

JobConfig parse_job_config(const nlohmann::json& c, int movable_joints,
                           const std::function<std::string(const std::string& hash)>& stored_model_bytes) {
  return parse_job_config(c, ModelFacts{movable_joints, {}, {}}, stored_model_bytes);
}

namespace {

// Throws when `bytes`, just read from `path`, are not those whose hash the job key recorded
// ("" = none recorded): the file changed after the sweep expanded, and the job would store
// results under a key that names other bytes.
void check_recorded_hash(const std::string& path, const std::string& bytes, const std::string& hash) {
  if (hash.empty()) return;
  const std::string now = calc_text_hash(bytes);
  if (now != hash) throw std::runtime_error(make_input_changed_text(path, hash, now));
}

// parse_job_config with each key's value found by `lookup(path)` (nullptr: the default).
// `recorded`: the recorded configuration, whose input hashes every file read is checked
// against; `contents`: a cache of those files keyed by their hashes (nullptr: read every file).
template <typename Lookup>
JobConfig parse_with(const Lookup& lookup, const ModelFacts& facts,
                     const std::function<std::string(const std::string& hash)>& stored_model_bytes,
                     const json* recorded_config = nullptr, JobFileContents* contents = nullptr) {
  JobConfig config;
  for (const JobConfigKey& key : job_config_keys()) {
    const json* value = lookup(key.path);
    if (value == nullptr || value->is_null()) continue;  // the default
    std::string suffix;
    const std::string problem = read_field_json(*value, key.field(config), suffix);
    if (!problem.empty()) throw ConfigError(key.path + suffix, problem);
  }
  // The runner reads files; the engine receives their content.
  RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  if (config.trajectory.kind == TrajectoryKind::recorded && !recorded.file.empty()) {
    const std::string hash = recorded_config ? find_recorded_input_hash(*recorded_config, "trajectory.recorded.file") : "";
    try {
      if (contents && !hash.empty() && hash == contents->recorded_hash) {
        recorded.samples = contents->recorded_samples;
        recorded.sample_lines = contents->recorded_lines;
      } else {
        const std::string bytes = read_input_file(recorded.file, InputFileKind::table);
        check_recorded_hash(recorded.file, bytes, hash);
        io::CsvTable table = io::parse_csv(bytes, recorded.file);
        recorded.samples = std::move(table.values);
        recorded.sample_lines = std::move(table.lines);
        if (contents && !hash.empty()) {
          contents->recorded_hash = hash;
          contents->recorded_samples = recorded.samples;
          contents->recorded_lines = recorded.sample_lines;
        }
      }
    } catch (const std::exception& error) {
      throw ConfigError("trajectory.recorded.file", error.what());
    }
  }
  const std::string& initial = config.learning.initial_model;
  if (!initial.empty()) {
    const std::string prefix = "stored:";
    try {
      if (initial.rfind(prefix, 0) == 0) {
        if (!stored_model_bytes) throw std::runtime_error("a stored model is read from its results database (armfarm run --db)");
        config.learning.initial_model_bytes = stored_model_bytes(initial.substr(prefix.size()));
      } else {
        const std::string hash = recorded_config ? find_recorded_input_hash(*recorded_config, "learning.initial_model") : "";
        if (contents && !hash.empty() && hash == contents->model_hash) {
          config.learning.initial_model_bytes = contents->model_bytes;
        } else {
          config.learning.initial_model_bytes = read_input_file(initial, InputFileKind::learner_model);
          check_recorded_hash(initial, config.learning.initial_model_bytes, hash);
          if (contents && !hash.empty()) {
            contents->model_hash = hash;
            contents->model_bytes = config.learning.initial_model_bytes;
          }
        }
      }
    } catch (const std::exception& error) {
      throw ConfigError("learning.initial_model", error.what());
    }
  }
  const std::vector<ConfigProblem> problems = validate(config, facts);
  if (!problems.empty()) {
    const std::string text = make_problems_text(problems);
    const std::string& path = problems.front().path;
    throw ConfigError(path, path.empty() ? text : text.substr(path.size() + 2));
  }
  return config;
}

}  // namespace

JobConfig parse_job_config(const nlohmann::json& c, const ModelFacts& facts,
                           const std::function<std::string(const std::string& hash)>& stored_model_bytes) {
  ValueFinder finder(c);
  return parse_with([&](const std::string& path) { return finder.find(path); }, facts, stored_model_bytes);
}

JobConfig parse_recorded_job_config(const nlohmann::json& recorded, const ModelFacts& facts,
                                    const std::function<std::string(const std::string& hash)>& stored_model_bytes,
                                    JobFileContents* contents) {
  const auto inputs = recorded.find("inputs");
  const bool records = inputs != recorded.end() && inputs->is_object() && !inputs->empty();
  ValueFinder finder(recorded);
  return parse_with(
      [&](const std::string& path) -> const json* {
        if (records && inputs->contains(path)) {
          if (const json* resolved = find_resolved_input(recorded, path)) return resolved;
        }
        return finder.find(path);
      },
      facts, stored_model_bytes, &recorded, contents);
}

}  // namespace armfarm
