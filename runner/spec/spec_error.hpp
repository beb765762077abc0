#pragma once
// The error of a sweep spec that cannot run: one line per problem, each naming the file and the
// JSON path ("sweeps/a.json: sweep.grid["control.kp[9]"]: ..."). `armfarm` prints them and
// exits 2 before touching any database.
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {

class SpecError : public std::runtime_error {
 public:
  explicit SpecError(std::vector<std::string> lines) : std::runtime_error(join(lines)), lines_(std::move(lines)) {}
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  static std::string join(const std::vector<std::string>& lines) {
    std::string text;
    for (const auto& line : lines) text += (text.empty() ? "" : "\n") + line;
    return text;
  }
  std::vector<std::string> lines_;
};

}  // namespace armfarm
