#include "runner/spec/input_files.hpp"

#include "engine/io/input_file.hpp"

#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_path.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace armfarm {
namespace {

// Why an input cannot be read (InputFileReader::read): what() is the one-line message, and
// `names_file` says whether it already begins with the resolved path, as known where it was
// thrown, so that record_input_files adds the path only where the message lacks it.
class InputReadError : public std::runtime_error {
 public:
  InputReadError(const std::string& message, bool names_file) : std::runtime_error(message), names_file_(names_file) {}
  bool names_file() const { return names_file_; }

 private:
  bool names_file_;
};

// The files `field` reads at `resolved_path`. The contract of a list_files: it throws InputFileError
// when its message names the resolved file first, any other std::exception when it does not (the
// model's: runner/execution/experiment_executor.cpp).
std::vector<std::string> list_input_files(const InputFileField& field, const std::string& resolved_path) {
  if (!field.list_files) return {resolved_path};
  try {
    return field.list_files(resolved_path);
  } catch (const InputFileError& error) {
    throw InputReadError(error.what(), true);
  } catch (const std::exception& error) {
    throw InputReadError(error.what(), false);
  }
}

// calc_file_hash of `absolute`, one of the files of the input at `resolved_path`: its
// InputFileError names `absolute` ("PATH: problem").
std::string hash_input_file(const std::string& absolute, const std::string& resolved_path) {
  try {
    return calc_file_hash(absolute);
  } catch (const InputFileError& error) {
    throw InputReadError(error.what(), absolute == resolved_path);
  }
}

// The recorded input fields of `config`: inputs entries that are not includes and whose path
// names a string element equal to the recorded "path".
template <typename Visit>
void visit_recorded_fields(const nlohmann::json& config, Visit visit) {
  const auto inputs = config.find("inputs");
  if (inputs == config.end() || !inputs->is_object()) return;
  for (const auto& [name, entry] : inputs->items()) {
    if (!entry.is_object() || entry.value("kind", "file") != "file") continue;
    ConfigPath segments;
    try {
      segments = parse_config_path(name);
    } catch (const std::invalid_argument&) {
      continue;
    }
    std::string problem;
    const nlohmann::json* element = find_config_element(config, segments, problem);
    if (element == nullptr || !element->is_string() || !entry.contains("path") || *element != entry["path"]) continue;
    visit(segments, entry);
  }
}

}  // namespace

std::string calc_resolved_path(const std::string& path, const std::string& folder) {
  std::filesystem::path p(path);
  if (p.is_relative()) p = std::filesystem::path(folder.empty() ? "." : folder) / p;
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(p, error);
  return (error ? p : absolute).lexically_normal().string();
}

std::string calc_file_hash(const std::string& path) { return calc_text_hash(read_input_file(path, InputFileKind::any)); }

std::string make_input_changed_text(const std::string& path, const std::string& recorded_hash, const std::string& now_hash) {
  return path + ": changed since the sweep was expanded (content hash " + now_hash.substr(0, 8) + ", the job key has " +
         recorded_hash.substr(0, 8) + "; run the sweep again and the job gets a new key)";
}

const InputFileReader::Content& InputFileReader::read(const InputFileField& field, const std::string& resolved_path) {
  const auto cache_key = std::make_pair(field.path, resolved_path);
  const auto found = cache_.find(cache_key);
  if (found != cache_.end()) return found->second;
  if (!std::filesystem::exists(resolved_path)) throw InputReadError(resolved_path + ": no such file", true);
  const std::vector<std::string> files = list_input_files(field, resolved_path);
  Content content;
  content.files = nlohmann::json::array();
  const std::filesystem::path folder = std::filesystem::path(resolved_path).parent_path();
  for (const std::string& file : files) {
    const std::string absolute = calc_resolved_path(file, folder.string());
    content.files.push_back({{"file", std::filesystem::path(absolute).lexically_relative(folder).generic_string()},
                             {"hash", hash_input_file(absolute, resolved_path)}});
  }
  if (content.files.empty()) content.files.push_back({{"file", std::filesystem::path(resolved_path).filename().string()},
                                                      {"hash", hash_input_file(resolved_path, resolved_path)}});
  // One file: its own hash (what `xxh128sum` prints); several: the hash of the list, whose
  // names are relative to the first file's folder, so moving the tree keeps it.
  content.hash = content.files.size() == 1 ? content.files[0]["hash"].get<std::string>()
                                           : calc_text_hash(calc_canonical_json(content.files));
  return cache_.emplace(cache_key, std::move(content)).first->second;
}

const std::string& InputFileReader::resolve(const std::string& path, const std::string& folder) {
  auto key = std::make_pair(path, folder);
  const auto found = resolved_.find(key);
  if (found != resolved_.end()) return found->second;
  return resolved_.emplace(std::move(key), calc_resolved_path(path, folder)).first->second;
}

std::vector<InputProblem> record_input_files(nlohmann::json& config, const std::vector<InputFileField>& fields,
                                             const std::function<std::string(const std::string&)>& folder_of,
                                             InputFileReader& reader) {
  std::vector<InputProblem> problems;
  nlohmann::json inputs = config.contains("inputs") && config["inputs"].is_object() ? config["inputs"] : nlohmann::json::object();
  for (const InputFileField& field : fields) {
    inputs.erase(field.path);
    std::string problem;
    const nlohmann::json* element = find_config_element(config, parse_config_path(field.path), problem);
    if (element == nullptr || !element->is_string() || element->get<std::string>().empty()) continue;
    if (field.is_read && !field.is_read(config)) continue;
    const std::string written = element->get<std::string>();
    const std::string resolved = reader.resolve(written, folder_of(field.path));
    try {
      const InputFileReader::Content& content = reader.read(field, resolved);
      inputs[field.path] = {{"path", written}, {"resolved", resolved}, {"hash", content.hash}, {"files", content.files}};
    } catch (const InputReadError& error) {
      problems.push_back({field.path, "'" + written + "' resolves to " + (error.names_file() ? "" : resolved + ": ") + error.what()});
    } catch (const std::exception& error) {
      problems.push_back({field.path, "'" + written + "' resolves to " + resolved + ": " + error.what()});
    }
  }
  if (inputs.empty()) {
    config.erase("inputs");
  } else {
    config["inputs"] = std::move(inputs);
  }
  return problems;
}

nlohmann::json calc_config_with_resolved_inputs(const nlohmann::json& config) {
  nlohmann::json result = config;
  visit_recorded_fields(config, [&](const ConfigPath& segments, const nlohmann::json& entry) {
    set_config_element(result, segments, entry.at("resolved"));
  });
  result.erase("inputs");
  return result;
}

const nlohmann::json* find_resolved_input(const nlohmann::json& config, const std::string& field) {
  const auto inputs = config.find("inputs");
  if (inputs == config.end() || !inputs->is_object()) return nullptr;
  const auto entry = inputs->find(field);
  if (entry == inputs->end() || !entry->is_object() || entry->value("kind", "file") != "file") return nullptr;
  const auto path = entry->find("path");
  const auto resolved = entry->find("resolved");
  if (path == entry->end() || resolved == entry->end()) return nullptr;
  ConfigPath segments;
  try {
    segments = parse_config_path(field);
  } catch (const std::invalid_argument&) {
    return nullptr;
  }
  std::string problem;
  const nlohmann::json* element = find_config_element(config, segments, problem);
  if (element == nullptr || !element->is_string() || *element != *path) return nullptr;
  return &*resolved;
}

std::string find_recorded_input_hash(const nlohmann::json& config, const std::string& field) {
  if (find_resolved_input(config, field) == nullptr) return "";
  const nlohmann::json& entry = config.at("inputs").at(field);
  const auto hash = entry.find("hash");
  return hash != entry.end() && hash->is_string() ? hash->get<std::string>() : "";
}

nlohmann::json make_job_key_document(const nlohmann::json& config) {
  const auto inputs = config.find("inputs");
  if (inputs == config.end()) return config;
  nlohmann::json document = config;
  visit_recorded_fields(config, [&](const ConfigPath& segments, const nlohmann::json& entry) {
    set_config_element(document, segments, "xxh3-128:" + entry.value("hash", std::string()));
  });
  nlohmann::json hashes = nlohmann::json::object();
  if (inputs->is_object()) {
    for (const auto& [name, entry] : inputs->items()) {
      if (entry.is_object()) hashes[name] = entry.value("hash", std::string());
    }
  }
  document["inputs"] = std::move(hashes);
  return document;
}

}  // namespace armfarm
