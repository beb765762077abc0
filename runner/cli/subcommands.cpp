// The one list of armfarm's subcommands (git's builtin table). Add a line per cmd_<name>.cpp.
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_run(CLI::App& parent);
RunFunction setup_job(CLI::App& parent);
RunFunction setup_expand(CLI::App& parent);
RunFunction setup_status(CLI::App& parent);
RunFunction setup_table(CLI::App& parent);
RunFunction setup_compare(CLI::App& parent);
RunFunction setup_export(CLI::App& parent);
RunFunction setup_plot(CLI::App& parent);
RunFunction setup_report(CLI::App& parent);
RunFunction setup_merge(CLI::App& parent);
RunFunction setup_lease(CLI::App& parent);
RunFunction setup_fit(CLI::App& parent);
RunFunction setup_lwpr(CLI::App& parent);
RunFunction setup_version(CLI::App& parent);
RunFunction setup_model(CLI::App& parent);
RunFunction setup_slurm(CLI::App& parent);

const std::vector<SubcommandEntry>& all_subcommands() {
  static const std::vector<SubcommandEntry> entries = {
      {"run", setup_run},
      {"job", setup_job},
      {"expand", setup_expand},
      {"status", setup_status},
      {"table", setup_table},
      {"compare", setup_compare},
      {"export", setup_export},
      {"plot", setup_plot},
      {"report", setup_report},
      {"merge", setup_merge},
      {"lease", setup_lease},
      {"fit", setup_fit},
      {"lwpr", setup_lwpr},
      {"version", setup_version},
      {"model", setup_model},
      {"slurm", setup_slurm},
  };
  return entries;
}

}  // namespace armfarm::cli
