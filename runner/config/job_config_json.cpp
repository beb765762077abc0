#include "runner/config/job_config_json.hpp"

#include "engine/experiment/job_config_validation.hpp"
#include "base/config_path.hpp"
#include "engine/io/input_file.hpp"
#include "runner/spec/config_error.hpp"
#include "runner/config/config_value_json.hpp"
#include "runner/io/csv_reader.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/input_files.hpp"

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace armfarm {
namespace {

using nlohmann::json;

/// Each key of job_config_keys() with its path parsed once (the table is built once per process).
const std::vector<ConfigPath>& job_config_key_paths() {
  static const std::vector<ConfigPath> paths = [] {
    std::vector<ConfigPath> parsed;
    for (const JobConfigKey& key : job_config_keys()) parsed.push_back(parse_config_path(key.path));
    return parsed;
  }();
  return paths;
}

/// The element one segment below `node`, nullptr when absent.
const json* find_child(const json& node, const PathSegment& segment) {
  if (segment.index) return node.is_array() && *segment.index < node.size() ? &node[*segment.index] : nullptr;
  if (!node.is_object()) return nullptr;
  const auto found = node.find(segment.key);
  return found == node.end() ? nullptr : &*found;
}

/// The value at the first `count` segments of `path`, nullptr when absent (no allocation: it runs
/// for every key of every job a sweep expands).
const json* find_value(const json& root, const ConfigPath& path, std::size_t count) {
  const json* node = &root;
  for (std::size_t i = 0; i < count && i < path.size() && node != nullptr; ++i) node = find_child(*node, path[i]);
  return node;
}

/// Whether two paths of the same length have the same parent (all but their last segment).
bool have_same_parent(const ConfigPath& a, const ConfigPath& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i + 1 < a.size(); ++i) {
    if (a[i] != b[i]) return false;
  }
  return true;
}

/// find_value for keys read in table order: keys of one parent object follow each other
/// (learning.lwpr.*), so the parent found for the last key is reused. The paths it is given
/// must outlive it (job_config_key_paths()).
class ValueFinder {
 public:
  explicit ValueFinder(const json& root) : root_(root) {}
  const json* find(const ConfigPath& path) {
    if (path.size() <= 1) return find_value(root_, path, path.size());
    if (last_ == nullptr || !have_same_parent(*last_, path)) parent_ = find_value(root_, path, path.size() - 1);
    last_ = &path;
    return parent_ == nullptr ? nullptr : find_child(*parent_, path.back());
  }

 private:
  const json& root_;
  const ConfigPath* last_ = nullptr;  // the path whose parent is parent_
  const json* parent_ = nullptr;
};

void set_value(json& root, const ConfigPath& path, json value) {
  json* node = &root;
  for (const PathSegment& segment : path) node = &(*node)[segment.key];  // key tables name no indices
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
  for (const RunnerConfigKey& key : runner_config_keys()) set_value(tree, parse_config_path(key.path), key.default_value);
  const std::vector<JobConfigKey>& keys = job_config_keys();
  for (std::size_t i = 0; i < keys.size(); ++i) set_value(tree, job_config_key_paths()[i], make_field_json(keys[i].field(defaults)));
  return tree;
}

nlohmann::json make_job_config_types() {
  JobConfig defaults;
  json tree = make_job_config_defaults();
  const std::vector<JobConfigKey>& keys = job_config_keys();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const ValueKind kind = keys[i].field(defaults).kind;
    if (kind == ValueKind::real_or_list || kind == ValueKind::real_matrix || kind == ValueKind::integer_or_auto ||
        kind == ValueKind::real_or_auto || kind == ValueKind::point_or_auto) {
      set_value(tree, job_config_key_paths()[i], nullptr);
    }
  }
  // A model file path or a stored-model reference object, resolved when the sweep expands.
  set_value(tree, parse_config_path("learning.initial_model"), nullptr);
  return tree;
}

ValidJobConfig parse_job_config(const nlohmann::json& c, int movable_joints,
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

// Records that `recorded`'s samples and lines (of content `hash`) are lent to the configuration
// being parsed: nothing is held until they come back.
void lend_recorded(JobFileContents& contents, const std::string& hash, const RecordedTrajectoryConfig& recorded) {
  contents.recorded_hash.clear();
  contents.recorded_samples = Eigen::MatrixXd();
  contents.recorded_lines = std::vector<int>();
  contents.lent_recorded = {hash, recorded.samples.data()};
}

void lend_model(JobFileContents& contents, const std::string& hash, const std::string& bytes) {
  contents.model_hash.clear();
  contents.model_bytes = std::string();
  contents.lent_model = {hash, bytes.data()};
}

// parse_job_config with each key's value found by `lookup(key, path)` (nullptr: the default).
// `recorded`: the recorded configuration, whose input hashes every file read is checked
// against; `contents`: a cache of those files keyed by their hashes (nullptr: read every file).
template <typename Lookup>
ValidJobConfig parse_with(const Lookup& lookup, const ModelFacts& facts,
                     const std::function<std::string(const std::string& hash)>& stored_model_bytes,
                     const json* recorded_config = nullptr, JobFileContents* contents = nullptr) {
  if (contents) {  // what an earlier call lent and was not returned is not taken back
    contents->lent_recorded = {};
    contents->lent_model = {};
  }
  JobConfig config;
  const std::vector<JobConfigKey>& keys = job_config_keys();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const JobConfigKey& key = keys[i];
    const json* value = lookup(key.path, job_config_key_paths()[i]);
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
        recorded.samples.swap(contents->recorded_samples);  // lent, until return_job_file_contents
        recorded.sample_lines.swap(contents->recorded_lines);
      } else {
        const std::string bytes = read_input_file(recorded.file, InputFileKind::table);
        check_recorded_hash(recorded.file, bytes, hash);
        io::CsvTable table = io::parse_csv(bytes, recorded.file);
        recorded.samples = std::move(table.values);
        recorded.sample_lines = std::move(table.lines);
      }
      if (contents && !hash.empty()) lend_recorded(*contents, hash, recorded);
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
          config.learning.initial_model_bytes.swap(contents->model_bytes);  // lent, until return_job_file_contents
        } else {
          config.learning.initial_model_bytes = read_input_file(initial, InputFileKind::learner_model);
          check_recorded_hash(initial, config.learning.initial_model_bytes, hash);
        }
        if (contents && !hash.empty()) lend_model(*contents, hash, config.learning.initial_model_bytes);
      }
    } catch (const std::exception& error) {
      throw ConfigError("learning.initial_model", error.what());
    }
  }
  std::variant<ValidJobConfig, std::vector<ConfigProblem>> checked = check_job_config(std::move(config), facts);
  if (const auto* problems = std::get_if<std::vector<ConfigProblem>>(&checked)) {
    // The first problem's path, and every problem in the message: "m1; p2: m2".
    const std::vector<ConfigProblem> others(problems->begin() + 1, problems->end());
    throw ConfigError(problems->front().path, problems->front().message + (others.empty() ? "" : "; " + make_problems_text(others)));
  }
  return std::get<ValidJobConfig>(std::move(checked));
}

}  // namespace

ValidJobConfig parse_job_config(const nlohmann::json& c, const ModelFacts& facts,
                           const std::function<std::string(const std::string& hash)>& stored_model_bytes) {
  ValueFinder finder(c);
  return parse_with([&](const std::string&, const ConfigPath& path) { return finder.find(path); }, facts, stored_model_bytes);
}

ValidJobConfig parse_recorded_job_config(const nlohmann::json& recorded, const ModelFacts& facts,
                                    const std::function<std::string(const std::string& hash)>& stored_model_bytes,
                                    JobFileContents* contents) {
  const auto inputs = recorded.find("inputs");
  const bool records = inputs != recorded.end() && inputs->is_object() && !inputs->empty();
  ValueFinder finder(recorded);
  return parse_with(
      [&](const std::string& text, const ConfigPath& path) -> const json* {
        if (records && inputs->contains(text)) {
          if (const json* resolved = find_resolved_input(recorded, text)) return resolved;
        }
        return finder.find(path);
      },
      facts, stored_model_bytes, &recorded, contents);
}

void return_job_file_contents(ValidJobConfig&& valid, JobFileContents& contents) {
  // `valid` is given up: its configuration is taken apart (moved, its storage keeps its address).
  JobConfig config = std::move(valid).release();
  RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  if (!contents.lent_recorded.hash.empty() && contents.lent_recorded.storage == recorded.samples.data()) {
    contents.recorded_hash = std::move(contents.lent_recorded.hash);
    contents.recorded_samples.swap(recorded.samples);
    contents.recorded_lines.swap(recorded.sample_lines);
  }
  contents.lent_recorded = {};
  std::string& bytes = config.learning.initial_model_bytes;
  if (!contents.lent_model.hash.empty() && contents.lent_model.storage == bytes.data()) {
    contents.model_hash = std::move(contents.lent_model.hash);
    contents.model_bytes.swap(bytes);
  }
  contents.lent_model = {};
}

}  // namespace armfarm
