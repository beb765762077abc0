#pragma once
// The error of a job configuration that is not valid, thrown by schema checks, parsers and
// executors and caught by the CLI, which prefixes the file name.
#include <stdexcept>
#include <string>

namespace armfarm {

/// A job configuration that is not valid. `json_path` is a configuration path's text
/// (base/config_path.hpp: "control.kp[2]", "trajectory.kind"), "" for the whole configuration;
/// what() is "path: message". Callers prefix the file name, and read the path and the message
/// apart from their accessors (never by cutting what() up).
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string json_path, std::string message)
      : std::runtime_error(json_path.empty() ? message : json_path + ": " + message),
        json_path_(std::move(json_path)),
        message_(std::move(message)) {}
  const std::string& json_path() const { return json_path_; }
  /// What is wrong, without the path.
  const std::string& message() const { return message_; }

 private:
  std::string json_path_;
  std::string message_;
};

}  // namespace armfarm
