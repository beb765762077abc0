#pragma once
// The files a job reads (its inputs: the arm model and its meshes, a recorded trajectory,
// included spec files) and how they enter the job key. A configuration records its inputs in a
// top-level "inputs" object (sweeps/README.md, "Input files"):
//
//   "inputs": {"model": {"path": "../models/arm.urdf",            // as written
//                        "resolved": "/home/me/armfarm/models/arm.urdf",
//                        "hash": "<XXH3-128 of the content, 32 hex digits>",
//                        "files": [{"file": "arm.urdf", "hash": "..."}, {"file": "meshes/l1.obj", ...}]},
//              "include[0]": {"path": "common.json", "resolved": "...", "hash": "...", "kind": "include"}}
//
// The key hashes the configuration with each recorded path replaced by its content hash, so it
// changes when a file's bytes change and not when the checkout moves.
#include "runner/spec/config_schema.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {

/// The absolute, lexically normal path of `path` written in a file in `folder` (an absolute
/// `path` stays as it is).
std::string calc_resolved_path(const std::string& path, const std::string& folder);

/// XXH3-128 of a file's bytes as 32 hex digits. Throws InputFileError (a std::runtime_error)
/// "PATH: problem" for anything but a regular file under the largest input cap.
std::string calc_file_hash(const std::string& path);

/// "PATH: changed since the sweep was expanded (content hash NOW, the job key has RECORDED; run
/// the sweep again and the job gets a new key)": a job refuses to run on such bytes.
std::string make_input_changed_text(const std::string& path, const std::string& recorded_hash, const std::string& now_hash);

/// Reads and hashes inputs, once per (field, resolved path): one per expansion or command.
class InputFileReader {
 public:
  struct Content {
    std::string hash;     ///< the file's hash if it reads only itself, else the hash of `files`
    nlohmann::json files;  ///< [{"file": path relative to the first file's folder, "hash": ...}]
  };
  /// Throws std::exception with a one-line message when the input cannot be read.
  const Content& read(const InputFileField& field, const std::string& resolved_path);
  /// calc_resolved_path(path, folder), computed once per pair.
  const std::string& resolve(const std::string& path, const std::string& folder);

 private:
  std::map<std::pair<std::string, std::string>, Content> cache_;
  std::map<std::pair<std::string, std::string>, std::string> resolved_;
};

/// A problem with one input: the field's dotted path and the message.
struct InputProblem {
  std::string field;
  std::string message;
};

/// Adds config["inputs"][field] for every field of `fields` the job reads (a non-empty string
/// value, and `is_read` true). `folder_of(field)` is the folder the field's value resolves
/// against (that of the file that wrote it). Keeps entries already in config["inputs"] that are
/// not fields (includes). Returns the inputs that cannot be read; they get no entry.
std::vector<InputProblem> record_input_files(nlohmann::json& config, const std::vector<InputFileField>& fields,
                                             const std::function<std::string(const std::string&)>& folder_of,
                                             InputFileReader& reader);

/// The configuration a job runs from: `config` without "inputs", with every recorded input field
/// set to its resolved path.
nlohmann::json calc_config_with_resolved_inputs(const nlohmann::json& config);

/// The resolved path `config` records for its input field `field` (the value
/// calc_config_with_resolved_inputs sets there), or nullptr when it records none for it.
const nlohmann::json* find_resolved_input(const nlohmann::json& config, const std::string& field);

/// The content hash `config` records for its input field `field`, "" when it records none or
/// when the field's value is not the path it records (so that another file is read).
std::string find_recorded_input_hash(const nlohmann::json& config, const std::string& field);

/// What the job key hashes: `config` with each recorded input's path replaced by
/// "xxh3-128:<hash>" and "inputs" reduced to {name: hash}; `config` itself when it records none.
nlohmann::json make_job_key_document(const nlohmann::json& config);

}  // namespace armfarm
