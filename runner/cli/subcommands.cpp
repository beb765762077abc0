// The one list of armfarm's subcommands (git's builtin table). Add a line per cmd_<name>.cpp.
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_version(CLI::App& parent);
RunFunction setup_expand(CLI::App& parent);
RunFunction setup_run(CLI::App& parent);
RunFunction setup_status(CLI::App& parent);
RunFunction setup_table(CLI::App& parent);
RunFunction setup_export(CLI::App& parent);
RunFunction setup_merge(CLI::App& parent);
RunFunction setup_compare(CLI::App& parent);
RunFunction setup_plot(CLI::App& parent);
RunFunction setup_report(CLI::App& parent);

const std::vector<SubcommandEntry>& all_subcommands() {
  static const std::vector<SubcommandEntry> entries = {
      {"version", setup_version},
      {"expand", setup_expand},
      {"run", setup_run},
      {"status", setup_status},
      {"table", setup_table},
      {"export", setup_export},
      {"merge", setup_merge},
      {"compare", setup_compare},
      {"plot", setup_plot},
      {"report", setup_report},
  };
  return entries;
}

}  // namespace armfarm::cli
