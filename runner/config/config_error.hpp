#pragma once
// The error of a job configuration that is not valid, thrown by schema checks, parsers and
// executors and caught by the CLI, which prefixes the file name.
#include <stdexcept>
#include <string>

namespace armfarm {

/// A job configuration that is not valid. `json_path` is a dotted path ("control.kp[2]",
/// "trajectory.kind"); callers prefix the file name.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string json_path, const std::string& message)
      : std::runtime_error(json_path.empty() ? message : json_path + ": " + message),
        json_path_(std::move(json_path)) {}
  const std::string& json_path() const { return json_path_; }

 private:
  std::string json_path_;
};

}  // namespace armfarm
