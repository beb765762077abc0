#pragma once
// A problem of a job configuration, as validation (job_config_validation.hpp) and the cost bound
// (job_workload.hpp) report it: the key path, what is wrong, and the unit and range when a value
// is outside its range.
#include "engine/config/config_key.hpp"

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm {

/// One problem: the key path ("trajectory.figure_eight.scale", "control.kp[2]") and what is
/// wrong, with the value, its unit and the allowed range.
struct ConfigProblem {
  std::string path;            ///< a configuration path's text (base/config_path.hpp); "" for the whole
  std::string message;         ///< what is wrong, without the path
  std::string unit;            ///< the key's unit ("rad", "s") when the value is outside its range, else ""
  std::optional<Range> range;  ///< the range the value is outside, else empty
};

/// A configuration problem found where a value is used rather than in validate() (the start
/// posture against the model a job runs on): what() is "path: message", and the problem is
/// carried whole so that a caller never cuts the text up.
class ConfigProblemError : public std::invalid_argument {
 public:
  explicit ConfigProblemError(ConfigProblem problem)
      : std::invalid_argument(problem.path.empty() ? problem.message : problem.path + ": " + problem.message),
        problem_(std::move(problem)) {}
  const ConfigProblem& problem() const { return problem_; }

 private:
  ConfigProblem problem_;
};

}  // namespace armfarm
