#pragma once
// Errors of the analysis commands: an unknown metric, parameter or sweep named by the user.
#include <stdexcept>

namespace armfarm {

class AnalysisError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace armfarm
