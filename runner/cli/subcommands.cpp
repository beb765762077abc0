// The one list of armfarm's subcommands (git's builtin table). Add a line per cmd_<name>.cpp.
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_version(CLI::App& parent);
RunFunction setup_model(CLI::App& parent);

const std::vector<SubcommandEntry>& all_subcommands() {
  static const std::vector<SubcommandEntry> entries = {
      {"version", setup_version},
      {"model", setup_model},
  };
  return entries;
}

}  // namespace armfarm::cli
