#pragma once
// What is wrong with a learner's parameter set (LWPR's, SSGPR's), as a value: the parameter,
// the element of a vector parameter, and the message, so that a caller maps it to its own key
// path (learning.lwpr.init_D) without reading it back out of an exception's text.
#include <optional>
#include <string>

namespace armfarm {

struct ParamProblem {
  std::string name;                ///< the parameter ("init_D"); "" when the problem is not one parameter's (the sizes)
  std::optional<int> element;      ///< 0-based element of a vector parameter ("norm_in[2]")
  std::string message;             ///< what is wrong, without the name ("must be symmetric")

  /// "init_D must be symmetric", "norm_in[2] must be finite and > 0", or the message alone.
  std::string describe() const {
    if (name.empty()) return message;
    return name + (element ? "[" + std::to_string(*element) + "]" : std::string()) + " " + message;
  }
};

}  // namespace armfarm
