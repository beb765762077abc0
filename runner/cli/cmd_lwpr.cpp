// `armfarm lwpr`: the group of LWPR commands (fit; more may follow).
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_lwpr_fit(CLI::App& group);

RunFunction setup_lwpr(CLI::App& parent) {
  CLI::App* group = parent.add_subcommand("lwpr", "LWPR learning on recorded data (fit)");
  group->require_subcommand(1);
  std::vector<std::pair<CLI::App*, RunFunction>> commands;
  const std::size_t before = group->get_subcommands({}).size();
  RunFunction fit = setup_lwpr_fit(*group);
  if (group->get_subcommands({}).size() > before) commands.emplace_back(group->get_subcommands({}).back(), fit);
  return [commands] {
    for (const auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
    return 2;
  };
}

}  // namespace armfarm::cli
